#!/usr/bin/env python3
"""The shape of the code, in figures: the largest files and functions outside tests, the Dispatcher's public
methods, repeated code outside tests, and the dependencies between top-level folders, which must hold no cycle.

    python3 bench/code_shape.py [REPO]        # REPO: a checkout (default: this one)

Functions are measured from universal-ctags' start and end lines; repeated code is the pairs of a `duplicates`
program when one is on PATH (skipped, saying so, otherwise); a dependency is an include of a header of another
folder ("common/text/utf8.h" in coordinator/ is coordinator → text). A folder's level is 0 when it includes no other folder, else one more than the highest it
includes.
"""
import collections
import json
import pathlib
import re
import shutil
import subprocess
import sys

SOURCE = re.compile(r"\.(cpp|h)$")
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)
SKIP = ("build", ".git", "tests", "experiments", "docs")


def sources(repo):
    for path in sorted(repo.rglob("*")):
        rel = path.relative_to(repo)
        if rel.parts[0] in SKIP or not SOURCE.search(path.name) or not path.is_file():
            continue
        yield rel


def lines(path):
    with open(path, encoding="utf-8", errors="replace") as f:
        return sum(1 for _ in f)


def largest_functions(repo, files, most):
    tags = subprocess.run(["ctags", "--output-format=json", "--fields=+neK", "--c++-kinds=f", "-f", "-"]
                          + [str(f) for f in files], cwd=repo, capture_output=True, text=True, check=True)
    found = []
    for line in tags.stdout.splitlines():
        tag = json.loads(line)
        if tag.get("kind") != "function" or "end" not in tag or tag["name"].startswith("__anon"):
            continue
        scope = tag.get("scope", "")
        name = (scope.split("::")[-1] + "::" if scope else "") + tag["name"]
        found.append((tag["end"] - tag["line"] + 1, f"{tag['path']}:{tag['line']} {name}"))
    return sorted(found, reverse=True)[:most]


def public_methods(repo, header, cls):
    tags = subprocess.run(["ctags", "--output-format=json", "--fields=+neaK", "--c++-kinds=+p", "-f", "-", header],
                          cwd=repo, capture_output=True, text=True, check=True)
    names = set()
    for line in tags.stdout.splitlines():
        tag = json.loads(line)
        if (tag.get("kind") in ("function", "prototype") and tag.get("access") == "public"
                and tag.get("scope", "").endswith(cls) and tag["name"] != cls):
            names.add(tag["name"])
    return sorted(names)


def folder_of(rel, depth):
    return "/".join(rel.parts[:depth]) if len(rel.parts) > depth else None


def dependencies(repo, files, depth=1):
    folders = {folder_of(f, depth) for f in files} - {None}
    edges = collections.defaultdict(set)
    for rel in files:
        own = folder_of(rel, depth)
        if own is None:
            continue
        for include in INCLUDE.findall((repo / rel).read_text(errors="replace")):
            other = "/".join(include.split("/")[:depth])
            if include.count("/") >= depth and other in folders and other != own:
                edges[own].add(other)
    return folders, edges


def levels(folders, edges):
    level, visiting = {}, set()

    def visit(folder, path):
        if folder in level:
            return level[folder]
        if folder in visiting:
            raise ValueError("cycle: " + " → ".join(path + [folder]))
        visiting.add(folder)
        level[folder] = 1 + max((visit(d, path + [folder]) for d in edges.get(folder, ())), default=-1)
        visiting.discard(folder)
        return level[folder]

    for folder in sorted(folders):
        visit(folder, [])
    return level


def duplicate_pairs(repo):
    tool = shutil.which("duplicates")  # a code-similarity tool, when installed; its figures are skipped otherwise
    if tool is None:
        return None
    out = subprocess.run([tool, "--repo", str(repo), "--most", "200", "--seconds", "120"], capture_output=True,
                         text=True).stdout
    rows = [l for l in out.splitlines() if re.match(r"^D\d+ ", l)]
    outside = [r for r in rows if not any(side.strip().startswith(("tests/", "experiments/"))
                                          for side in r.split(" ", 1)[1].split(" ~ "))]
    return len(rows), outside


def main():
    repo = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).resolve().parent.parent)
    files = list(sources(repo))
    print(f"{len(files)} source files, {sum(lines(repo / f) for f in files)} lines outside tests, experiments, docs")
    print("largest files:")
    for n, f in sorted(((lines(repo / f), f) for f in files), reverse=True)[:5]:
        print(f"  {n:5d}  {f}")
    print("largest functions:")
    for n, where in largest_functions(repo, files, 8):
        print(f"  {n:5d}  {where}")
    methods = public_methods(repo, "coordinator/dispatch/dispatcher.h", "Dispatcher")
    print(f"Dispatcher's public methods: {len(methods)} ({', '.join(methods)})")
    # verification's one home, where there is one: the events it takes and what it is asked
    if (repo / "coordinator/trust/referee.h").exists():
        methods = public_methods(repo, "coordinator/trust/referee.h", "Referee")
        print(f"Referee's public methods: {len(methods)} ({', '.join(methods)})")
    duplicates = duplicate_pairs(repo)
    if duplicates is None:
        print("repeated code: not measured (no duplicates program on PATH)")
    else:
        total, outside = duplicates
        print(f"repeated code (duplicates --most 200): {total} pairs, {len(outside)} outside tests and experiments")
        for row in outside:
            print("  " + row)
    folders, edges = dependencies(repo, files)
    level = levels(folders, edges)
    print(f"folders: {len(folders)} on {max(level.values()) + 1} levels, {sum(map(len, edges.values()))} "
          "dependencies, no cycle (a cycle stops this script, naming it)")
    for folder in sorted(folders, key=lambda f: (level[f], f)):
        print(f"  {level[folder]}  {folder:14s} → {', '.join(sorted(edges.get(folder, ()))) or '—'}")
    inner = [f for f in files if f.parts[0] == "coordinator"]
    folders, edges = dependencies(repo, inner, depth=2)
    level = levels(folders, edges)
    print(f"coordinator's parts: {len(folders)}, no cycle")
    for folder in sorted(folders, key=lambda f: (level[f], f)):
        print(f"  {level[folder]}  {folder:22s} → {', '.join(sorted(edges.get(folder, ()))) or '—'}")


if __name__ == "__main__":
    main()
