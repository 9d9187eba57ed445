#!/usr/bin/env python3
"""The release's files agree with its one version, CMake's PROJECT_VERSION in the top CMakeLists.txt:
CITATION.cff parses (PyYAML) as Citation File Format 1.2.0 with that version and the Apache-2.0 licence;
CHANGELOG.md's newest release is that version; LICENSE is the Apache License 2.0 text as the Apache Software
Foundation publishes it (its SHA-256, and Debian's copy where installed); NOTICE exists and credits what the project
reimplements and builds; deploy/Dockerfile labels the image with that version (its POET_VERSION argument's
default, so that every build is labelled) and checks the argument against the build.

Usage: check_release_files.py SOURCE_DIR"""

import hashlib
import os
import re
import sys

# sha256sum of https://www.apache.org/licenses/LICENSE-2.0.txt (and of Debian's /usr/share/common-licenses/Apache-2.0)
APACHE_2_SHA256 = "cfc7749b96f63bd31c3c42b5c471bf756814053e847c10f3eb003417bc523d30"
DEBIAN_APACHE_2 = "/usr/share/common-licenses/Apache-2.0"

failures = []


def expect(condition, message):
    if not condition:
        failures.append(message)


def read(root, name):
    with open(os.path.join(root, name), encoding="utf-8") as f:
        return f.read()


def project_version(root):
    match = re.search(r"^project\(poet VERSION ([0-9]+\.[0-9]+\.[0-9]+)\b", read(root, "CMakeLists.txt"), re.M)
    if not match:
        sys.exit("CMakeLists.txt: no 'project(poet VERSION X.Y.Z' line")
    return match.group(1)


def check_citation(root, version):
    import yaml  # python3-yaml (deploy/install-deps.sh's test packages)
    citation = yaml.safe_load(read(root, "CITATION.cff"))
    expect(isinstance(citation, dict), "CITATION.cff: not a mapping")
    if not isinstance(citation, dict):
        return
    expect(citation.get("cff-version") == "1.2.0", f"CITATION.cff: cff-version {citation.get('cff-version')!r}")
    for key in ("message", "title", "authors", "version", "license"):
        expect(key in citation, f"CITATION.cff: no {key}")
    expect(citation.get("version") == version,
           f"CITATION.cff: version {citation.get('version')!r}, CMakeLists.txt's PROJECT_VERSION {version}")
    expect(citation.get("license") == "Apache-2.0", f"CITATION.cff: license {citation.get('license')!r}")
    expect(citation.get("authors") == [{"name": "The poet authors"}], "CITATION.cff: authors is not the entity")
    preferred = citation.get("preferred-citation") or {}
    expect(preferred.get("doi") == "10.1145/3321707.3321799", "CITATION.cff: the preferred citation is not GECCO 2019")
    values = [i.get("value") for r in citation.get("references", []) for i in r.get("identifiers", [])]
    expect("arXiv:1901.01753" in values, "CITATION.cff: no reference to arXiv:1901.01753")


def check_release_date(root):
    """CITATION.cff's date-released is the newest release's date in CHANGELOG.md."""
    import yaml
    citation = yaml.safe_load(read(root, "CITATION.cff"))
    released = re.findall(r"^## \[[0-9.]+\] - (\d{4}-\d{2}-\d{2})", read(root, "CHANGELOG.md"), re.M)
    date = str(citation.get("date-released")) if isinstance(citation, dict) else None
    expect(released and date == released[0],
           f"CITATION.cff: date-released {date}, CHANGELOG.md's newest release {released[0] if released else None}")


def check_changelog(root, version):
    releases = re.findall(r"^## \[([^\]]+)\](?: - (\d{4}-\d{2}-\d{2}))?", read(root, "CHANGELOG.md"), re.M)
    named = [(name, date) for name, date in releases if name != "Unreleased"]
    expect(named, "CHANGELOG.md: no release heading '## [X.Y.Z] - YYYY-MM-DD'")
    if named:
        expect(named[0][0] == version,
               f"CHANGELOG.md: newest release {named[0][0]}, CMakeLists.txt's PROJECT_VERSION {version}")
    for name, date in named:
        expect(re.fullmatch(r"[0-9]+\.[0-9]+\.[0-9]+", name) and date, f"CHANGELOG.md: release heading {name!r}")


def check_license(root):
    with open(os.path.join(root, "LICENSE"), "rb") as f:
        text = f.read()
    expect(hashlib.sha256(text).hexdigest() == APACHE_2_SHA256, "LICENSE: not the Apache License 2.0 text verbatim")
    if os.path.exists(DEBIAN_APACHE_2):
        with open(DEBIAN_APACHE_2, "rb") as f:
            expect(f.read() == text, f"LICENSE: differs from {DEBIAN_APACHE_2}")
    notice = read(root, "NOTICE")
    for credit in ("The poet authors", "uber-research/poet", "OpenAI Gym", "Box2D", "arXiv:1901.01753"):
        expect(credit in notice, f"NOTICE: does not credit {credit}")


def check_image_labels(root, version):
    dockerfile = read(root, os.path.join("deploy", "Dockerfile"))
    for label, value in (("version", "${POET_VERSION}"), ("licenses", "Apache-2.0")):
        expect(f'org.opencontainers.image.{label}="{value}"' in dockerfile,
               f"deploy/Dockerfile: no label org.opencontainers.image.{label}={value}")
    # the argument's default, in the global scope (before the first FROM), is the project's version
    preamble = dockerfile.split("\nFROM ", 1)[0]
    default = re.search(r"^ARG POET_VERSION=(\S*)$", preamble, re.M)
    expect(default and default.group(1) == version,
           f"deploy/Dockerfile: ARG POET_VERSION={default.group(1) if default else '(none before the first FROM)'}, "
           f"CMakeLists.txt's PROJECT_VERSION {version}")
    # the build stage refuses an argument that is not the version it built
    expect(re.search(r'poet-coordinator --fingerprint.*\$POET_VERSION', dockerfile, re.S),
           "deploy/Dockerfile: the build stage does not check POET_VERSION against the built binary")


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    root = sys.argv[1]
    version = project_version(root)
    check_citation(root, version)
    check_changelog(root, version)
    check_release_date(root)
    check_license(root)
    check_image_labels(root, version)
    for failure in failures:
        print(failure)
    print(f"release files of {version}: {'FAIL' if failures else 'ok'}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
