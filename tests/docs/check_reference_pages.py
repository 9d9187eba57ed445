#!/usr/bin/python3
"""The reference pages of the documentation site (docs/reference/<page>.md) are what poet-reference prints now.

Each page is generated from the code by `poet-reference <page>` run in the source tree; a committed page that
differs from it is out of date (a field, a default, a bound or a comment changed without the page). The failure
shows the first lines of the difference and the command that regenerates the page.

Usage: check_reference_pages.py --tool BUILD/tools/poet-reference --source SRC PAGE [PAGE...]

A page's subcommand takes the options listed in PAGE_ARGS (paths relative to the source tree); a page not listed
there takes none. Debian's python3, stdlib only.
"""

import argparse
import difflib
import os
import subprocess
import sys

# The options of each page's subcommand, as the regenerating command writes them (run from the source tree).
PAGE_ARGS = {
    "config": ["--configs", "deploy/configs"],
    "http": ["--examples", "docs/reference/examples"],
}


def regenerate_command(page):
    return " ".join(["build/tools/poet-reference", page, *PAGE_ARGS.get(page, []),
                     "--out", f"docs/reference/{page}.md"])


def check_page(tool, source, page):
    """None when the committed page is current, else a message saying how it differs and how to remake it."""
    committed_path = os.path.join(source, "docs", "reference", f"{page}.md")
    command = [os.path.abspath(tool), page, *PAGE_ARGS.get(page, [])]  # run from the source tree
    try:
        made = subprocess.run(command, cwd=source, capture_output=True, timeout=60, check=False)
    except subprocess.TimeoutExpired:
        return f"{' '.join(command)}: no answer within 60 s"
    if made.returncode != 0:
        return (f"{' '.join(command)} exited with {made.returncode}: "
                f"{made.stderr.decode('utf-8', 'replace').strip()}")
    generated = made.stdout.decode("utf-8")
    try:
        with open(committed_path, encoding="utf-8") as f:
            committed = f.read()
    except OSError as e:
        return (f"docs/reference/{page}.md: {e.strerror}; make it with (from the source tree):\n"
                f"  {regenerate_command(page)}")
    if committed == generated:
        return None
    diff = list(difflib.unified_diff(committed.splitlines(), generated.splitlines(),
                                     f"docs/reference/{page}.md (committed)", f"poet-reference {page} (now)",
                                     lineterm="", n=1))
    shown = "\n".join(diff[:40]) + ("\n..." if len(diff) > 40 else "")
    return (f"docs/reference/{page}.md is out of date; remake it with (from the source tree):\n"
            f"  {regenerate_command(page)}\n{shown}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tool", required=True, help="the built poet-reference")
    parser.add_argument("--source", required=True, help="the source tree")
    parser.add_argument("pages", nargs="+", help="pages of docs/reference/, by name (config, ...)")
    args = parser.parse_args()
    failures = 0
    for page in args.pages:
        problem = check_page(args.tool, args.source, page)
        if problem is None:
            print(f"docs/reference/{page}.md: current")
        else:
            print(problem, file=sys.stderr)
            failures += 1
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
