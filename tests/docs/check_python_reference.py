#!/usr/bin/python3
"""The Python module's reference pages are what their generators print now: docs/reference/python.md (from the
module's docstrings, tools/reference/python_reference.py) and docs/reference/environment.md (the walker's card,
tools/reference/environment_card.py).

Each generator imports the built module; a committed page that differs from its output is out of date (a
docstring, a name, a bound or a constant changed without the page). The failure shows the first lines of the
difference and the command that regenerates the page.

Usage: check_python_reference.py --source SRC --pythonpath BUILD/python

Debian's python3, stdlib only (the generators need numpy and the built module).
"""

import argparse
import os
import subprocess
import sys

from check_reference_pages import compare_page, report_pages  # beside this file

# page of docs/reference/ -> its generator, relative to the source tree
PAGES = {
    "python": "tools/reference/python_reference.py",
    "environment": "tools/reference/environment_card.py",
}


def regenerate_command(page):
    return f"PYTHONPATH=build/python /usr/bin/python3 {PAGES[page]} --out docs/reference/{page}.md"


def check_page(source, pythonpath, page):
    """None when the committed page is current, else a message saying how it differs and how to remake it."""
    command = [sys.executable, os.path.join(source, PAGES[page])]
    env = dict(os.environ, PYTHONPATH=os.path.abspath(pythonpath))
    try:
        made = subprocess.run(command, cwd=source, env=env, capture_output=True, timeout=120, check=False)
    except subprocess.TimeoutExpired:
        return f"{PAGES[page]}: no answer within 120 s"
    if made.returncode != 0:
        return f"{PAGES[page]} exited with {made.returncode}: {made.stderr.decode('utf-8', 'replace').strip()}"
    return compare_page(source, page, made.stdout.decode("utf-8"), PAGES[page], regenerate_command(page))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--source", required=True, help="the source tree")
    parser.add_argument("--pythonpath", required=True, help="the directory the built module poet is in")
    parser.add_argument("pages", nargs="*", default=list(PAGES), help="pages of docs/reference/ (default: both)")
    args = parser.parse_args()
    return report_pages(args.pages, lambda page: check_page(args.source, args.pythonpath, page))


if __name__ == "__main__":
    sys.exit(main())
