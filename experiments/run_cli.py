"""The command line the scripts that read one run share: a run directory, opened read-only with the Python module
(a run that cannot be read is a usage error naming why)."""

import argparse

import poet


def run_parser(doc):
    """An argument parser described by the script's docstring's first line, with the run directory argument."""
    parser = argparse.ArgumentParser(description=doc.splitlines()[0])
    parser.add_argument("run_dir", help="a run directory (live or finished; nothing is written to it)")
    return parser


def open_run(parser, run_dir):
    """The run in run_dir, or the parser's usage error."""
    try:
        return poet.Run(run_dir)
    except ValueError as error:
        parser.error(str(error))
