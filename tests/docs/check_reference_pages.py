#!/usr/bin/python3
"""The reference pages of the documentation site (docs/reference/<page>.md) are what poet-reference prints now.

Each page is generated from the code by `poet-reference <page>` run in the source tree; a committed page that
differs from it is out of date (a field, a default, a bound, a comment or a flag changed without the page). The
failure shows the first lines of the difference and the command that regenerates the page.

Usage: check_reference_pages.py --tool BUILD/tools/poet-reference --source SRC [--build BUILD] PAGE [PAGE...]

A page's subcommand takes the options listed in PAGE_ARGS (paths relative to the source tree, or {build}: the
build tree, whose binaries the cli page runs); a page not listed there takes none. Debian's python3, stdlib only.
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
    "cli": ["--binaries", "{build}"],
}


def page_args(page, build):
    return [arg.replace("{build}", build) for arg in PAGE_ARGS.get(page, [])]


def regenerate_command(tool, source, build, page):
    """The command that remakes the page, run from the source tree: paths inside it relative, as a reader types them."""
    def shown(path):
        relative = os.path.relpath(os.path.abspath(path), os.path.abspath(source))
        return path if relative.startswith("..") else relative
    return " ".join([shown(tool), page, *page_args(page, shown(build)), "--out", f"docs/reference/{page}.md"])


def check_page(tool, source, build, page):
    """None when the committed page is current, else a message saying how it differs and how to remake it."""
    command = [os.path.abspath(tool), page, *page_args(page, os.path.abspath(build))]  # run from the source tree
    try:
        made = subprocess.run(command, cwd=source, capture_output=True, timeout=60, check=False)
    except subprocess.TimeoutExpired:
        return f"{' '.join(command)}: no answer within 60 s"
    if made.returncode != 0:
        return (f"{' '.join(command)} exited with {made.returncode}: "
                f"{made.stderr.decode('utf-8', 'replace').strip()}")
    return compare_page(source, page, made.stdout.decode("utf-8"), f"poet-reference {page}",
                        regenerate_command(tool, source, build, page))


def compare_page(source, page, generated, generator, regenerate):
    """None when docs/reference/<page>.md is `generated`, else a message with the difference and `regenerate`, the
    command that remakes the page (also used by check_python_reference.py)."""
    committed_path = os.path.join(source, "docs", "reference", f"{page}.md")
    try:
        with open(committed_path, encoding="utf-8") as f:
            committed = f.read()
    except OSError as e:
        return f"docs/reference/{page}.md: {e.strerror}; make it with (from the source tree):\n  {regenerate}"
    if committed == generated:
        return None
    diff = list(difflib.unified_diff(committed.splitlines(), generated.splitlines(),
                                     f"docs/reference/{page}.md (committed)", f"{generator} (now)",
                                     lineterm="", n=1))
    shown = "\n".join(diff[:40]) + ("\n..." if len(diff) > 40 else "")
    return f"docs/reference/{page}.md is out of date; remake it with (from the source tree):\n  {regenerate}\n{shown}"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--tool", required=True, help="the built poet-reference")
    parser.add_argument("--source", required=True, help="the source tree")
    parser.add_argument("--build", help="the build tree (default: the one holding --tool, BUILD/tools/poet-reference)")
    parser.add_argument("pages", nargs="+", help="pages of docs/reference/, by name (config, ...)")
    args = parser.parse_args()
    build = args.build or os.path.dirname(os.path.dirname(os.path.abspath(args.tool)))
    return report_pages(args.pages, lambda page: check_page(args.tool, args.source, build, page))


def report_pages(pages, check):
    """Prints what check(page) finds of each page (None: current); the exit code, 1 when any is not current."""
    failures = 0
    for page in pages:
        problem = check(page)
        if problem is None:
            print(f"docs/reference/{page}.md: current")
        else:
            print(problem, file=sys.stderr)
            failures += 1
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
