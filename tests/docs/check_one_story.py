#!/usr/bin/python3
"""The documentation tells one story: what two places say of one thing, they say alike.

    check_one_story.py --source SRC

Checks the pages of the site (docs/**/*.md), README.md and the deploy READMEs, and the presets of deploy/configs:
- no page shows a path of the machine a capture was made on (/work/..., /home/..., /root/..., /tmp/...): a reader's
  checkout is elsewhere;
- the quick preset's run directory is out/quick on every page (out/quick-NAME for a run of its own), and a
  container's run directory is /var/lib/poet/runs/PRESET, on the pages and in the manifests;
- the paper's ES-alone peak is quoted as one range wherever it is quoted, and that range spans the per-course
  peaks a page gives;
- the verdicts agree: each row of README's table has the verdict of the results' row of the same claim, and each
  results page states exactly the verdicts the results' rows that link it give;
- a worker machine runs one poet-worker process per core (--threads 1) in every command a page shows;
- the presets' comments are true where they can be checked: a "# paper" or "# reference" on a field's line (with
  or without ": VALUE") is the paper preset's value or the schema's default (read from the generated config
  reference), paper.textproto writes out every field as its header says, and a preset whose comment says it is
  made from another names it in a derives-from line (so that the config reference lists where the two differ).

Debian's python3, stdlib only."""

import argparse
import glob
import os
import re
import sys

# Paths of the machine a page's output was captured on: a page shows run directories relative to the repository.
MACHINE_PATH = re.compile(r"(?<![\w.~-])/(?:work|home|root|Users|tmp)/[\w.@%+-]+")
VERDICT = re.compile(r"\*\*(reproduced|partly|not reached)\*\*")
PAGE_VERDICT = re.compile(r"\*\*[^*\n]*?[Vv]erdict: (reproduced|partly|not reached)\b")


class Checker:
    def __init__(self):
        self.errors = []

    def expect(self, condition, message):
        if not condition:
            self.errors.append(message)
        return condition


def read(path):
    with open(path, encoding="utf-8") as f:
        return f.read()


def pages(source):
    """{path relative to source: text} of the site's pages, README.md and the deploy READMEs."""
    found = sorted(glob.glob(os.path.join(source, "docs", "**", "*.md"), recursive=True))
    found += [os.path.join(source, "README.md")]
    found += sorted(glob.glob(os.path.join(source, "deploy", "**", "README.md"), recursive=True))
    return {os.path.relpath(p, source): read(p) for p in found if os.path.isfile(p)}


def commands(text):
    """Every command line a page shows: the lines of its code blocks (continuations joined) and its inline code."""
    out = []
    for block in re.findall(r"```[a-z]*\n(.*?)\n```", text, re.S):
        out += [line.strip() for line in block.replace("\\\n", " ").split("\n")]
    out += re.findall(r"`([^`\n]+)`", re.sub(r"```.*?```", "", text, flags=re.S))
    return out


def check_machine_paths(check, texts):
    for name, text in texts.items():
        for n, line in enumerate(text.split("\n"), 1):
            for path in MACHINE_PATH.findall(line):
                check.expect(False, f"{name}:{n}: {path}, a path of the machine a capture was made on: "
                             "show a path relative to the checkout (or ... for its start)")


def check_run_directories(check, texts, source):
    for name, text in texts.items():
        for command in commands(text):
            if "quick.textproto" not in command or "--run-dir" not in command:
                continue
            run_dir = re.search(r"--run-dir\s+(\S+)", command).group(1)
            check.expect(re.fullmatch(r"out/quick(-[\w-]+)?|/var/lib/poet/runs/quick", run_dir) is not None,
                         f"{name}: a run of the quick preset in {run_dir}, where every other page has out/quick "
                         f"(out/quick-NAME for a run of its own): {command}")
        for n, line in enumerate(text.split("\n"), 1):
            check.expect(re.search(r"/var/lib/poet/run\b(?!s)", line) is None,
                         f"{name}:{n}: /var/lib/poet/run, where the containers' run directory is "
                         "/var/lib/poet/runs/PRESET")
    for manifest in glob.glob(os.path.join(source, "deploy", "**", "*.y*ml"), recursive=True):
        check.expect(re.search(r"/var/lib/poet/run\b(?!s)", read(manifest)) is None,
                     f"{os.path.relpath(manifest, source)}: /var/lib/poet/run, where the pages have "
                     "/var/lib/poet/runs/PRESET")


def check_paper_peaks(check, texts):
    quoted = {}
    for name, text in texts.items():
        flat = re.sub(r"\s+", " ", text)
        for match in re.finditer(r"ES alone[^.|]*?peak\w* at (\d+\.\d)–(\d+\.\d)", flat):
            quoted.setdefault((match.group(1), match.group(2)), []).append(name)
        for match in re.finditer(r"peak\w* at (\d+\.\d)–(\d+\.\d) [^.|]*?\(((?:\d+\.\d on [a-z ]+,? ?)+)\)", flat):
            parts = [float(x) for x in re.findall(r"(\d+\.\d) on", match.group(3))]
            check.expect((min(parts), max(parts)) == (float(match.group(1)), float(match.group(2))),
                         f"{name}: the paper's ES-alone peak {match.group(1)}–{match.group(2)} does not span the "
                         f"per-course peaks it gives ({match.group(3)})")
        for match in re.finditer(r"paper's peaked at (\d+\.\d)–(\d+\.\d)", flat):
            quoted.setdefault((match.group(1), match.group(2)), []).append(name)
    check.expect(len(quoted) <= 1, "the paper's ES-alone peak is quoted as several ranges: " +
                 "; ".join(f"{lo}–{hi} in {', '.join(sorted(set(where)))}" for (lo, hi), where in quoted.items()))


def table_rows(text, header_start):
    """The rows of the first table whose header line starts with header_start, as lists of cells."""
    lines = text.split("\n")
    for i, line in enumerate(lines):
        if line.startswith(header_start):
            rows = []
            for row in lines[i + 2:]:
                if not row.startswith("|"):
                    break
                rows.append([c.strip() for c in row.strip().strip("|").split(" | ")])
            return rows
    return []


def words(claim):
    return set(re.findall(r"[a-zà-ÿθ]+", claim.lower())) - {"the", "and", "of", "a", "what", "enhanced", "poet"}


def check_verdicts(check, texts):
    index = texts.get("docs/results/index.md", "")
    results = []  # (claim, verdict, linked page)
    for cells in table_rows(index, "| claim | paper |"):
        verdict = VERDICT.search(cells[3])
        link = re.search(r"\]\(([\w-]+\.md)", cells[4])
        if check.expect(verdict is not None and link is not None, f"docs/results/index.md: a row without verdict "
                        f"or page: {cells[0]}"):
            results.append((cells[0], verdict.group(1), link.group(1)))
    for cells in table_rows(texts.get("README.md", ""), "| claim | verdict |"):
        verdict = VERDICT.search(cells[1])
        best = max(results, key=lambda r: len(words(r[0]) & words(cells[0])) / len(words(r[0]) | words(cells[0])),
                   default=None)
        if check.expect(verdict is not None and best is not None, f"README.md: no verdict for '{cells[0]}'"):
            check.expect(verdict.group(1) == best[1], f"README.md gives '{cells[0]}' the verdict {verdict.group(1)}, "
                         f"docs/results/index.md gives '{best[0]}' {best[1]}")
    for page in sorted({r[2] for r in results}):
        given = {r[1] for r in results if r[2] == page}
        stated = set(PAGE_VERDICT.findall(re.sub(r"\s+", " ", texts.get("docs/results/" + page, ""))))
        check.expect(stated == given, f"docs/results/{page} states the verdicts {sorted(stated)}, the results' rows "
                     f"that link it give {sorted(given)}")


def check_worker_threads(check, texts):
    for name, text in texts.items():
        for command in commands(text):
            match = re.search(r"poet-worker\b[^#]*?--threads[ =](\S+)", command)
            if match:
                check.expect(match.group(1) == "1" or match.group(1).startswith(("$", '"$')),
                             f"{name}: a worker machine runs one poet-worker process per core (--threads 1; "
                             f"docs/cluster.md measures why), this page shows --threads {match.group(1)}: {command}")


def preset_fields(text):
    """{dotted path: (value, comment on its line)} of a preset's scalar fields."""
    fields, stack = {}, []
    for line in text.split("\n"):
        code, _, comment = line.partition("#")
        code = code.strip()
        if not code:
            continue
        opened = re.fullmatch(r"(\w+)\s*\{", code)
        if opened:
            stack.append(opened.group(1))
        elif code == "}":
            stack.pop()
        elif re.fullmatch(r"(\w+)\s*:\s*(\S+)", code) and "{" not in code:
            name, value = re.fullmatch(r"(\w+)\s*:\s*(\S+)", code).groups()
            fields[".".join(stack + [name])] = (value.strip('"'), comment.strip())
    return fields


def same_value(a, b):
    try:
        return float(a) == float(b)
    except ValueError:
        return a == b


def check_presets(check, source):
    reference = read(os.path.join(source, "docs", "reference", "config.md"))
    defaults = {}
    for match in re.finditer(r"^\| `([\w.]+)` \| [\w ]+ \| `([^`]*)` \| ", reference, re.M):
        defaults.setdefault(match.group(1), match.group(2).strip('"'))
    configs = os.path.join(source, "deploy", "configs")
    paper_text = read(os.path.join(configs, "paper.textproto"))
    paper = {path: value for path, (value, _) in preset_fields(paper_text).items()}
    for path in sorted(glob.glob(os.path.join(configs, "*.textproto"))):
        name, text = os.path.basename(path), read(path)
        for field, (value, comment) in preset_fields(text).items():
            for source_name, values in (("paper", paper), ("reference", defaults)):
                claim = re.match(source_name + r"(?::\s*([\w.+-]+))?(?=$|[;,.]\s|[;,.]$|\s\(|\s*$)", comment)
                if not claim or field not in values:
                    continue
                said = claim.group(1) or value
                check.expect(same_value(said, values[field]),
                             f"deploy/configs/{name}: {field}: the comment says the {source_name}'s value is {said}, "
                             f"the {'paper preset' if source_name == 'paper' else 'schema default'} is {values[field]}")
        header = "\n".join(line for line in text.split("\n") if line.startswith("#"))
        based = re.search(r"(?:preset \((\w+)\.textproto\) with|[Ss]ized like (\w+)\.textproto)", header)
        derives = re.search(r"^# derives-from: (\S+)", header, re.M)
        if based:
            base = (based.group(1) or based.group(2)) + ".textproto"
            check.expect(derives is not None and derives.group(1) == base,
                         f"deploy/configs/{name}: its comment makes it from {base}, but no '# derives-from: {base}' "
                         "line says so (the config reference lists where the two differ from that line)")
    if "Every field is written out" in paper_text:
        sections = ("", "es.", "poet.", "poet.mutation.", "walker.")
        for field in defaults:
            parent = field.rsplit(".", 1)[0] + "." if "." in field else ""
            if parent in sections and field not in ("es", "poet", "walker", "es_alone", "direct_path",
                                                    "poet.mutation"):
                check.expect(field in paper, f"deploy/configs/paper.textproto says every field is written out, "
                             f"but {field} is not")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--source", required=True, help="the repository root")
    args = parser.parse_args()
    texts = pages(args.source)
    check = Checker()
    for step in (check_machine_paths, check_paper_peaks, check_verdicts, check_worker_threads):
        step(check, texts)
    check_run_directories(check, texts, args.source)
    check_presets(check, args.source)
    if check.errors:
        print("\n".join(check.errors), file=sys.stderr)
        return 1
    print(f"one story: {len(texts)} pages and the presets agree")
    return 0


if __name__ == "__main__":
    sys.exit(main())
