#!/usr/bin/python3
"""Nothing on the path from a config to a checkpoint calls the C library's transcendental functions.

glibc picks among builds of exp, log, sin, cos, pow and the rest by the processor's features, and other C libraries
and versions compute other last bits; the project computes its own (math/). This check reads the sources of the
folders on that path — the simulation, the engine, the formats, the run directory, the coordinator and the worker,
and the project's glue to Box2D — and fails naming every call of one of those functions (std:: or not, float or
double) outside a comment or a string. The C library's functions behind the project's math API for comparisons
(math/c_library_math.cpp) and the drawing code (pictures/, report/, tools/) are off that path.

Usage: check_own_math.py SOURCE_DIR
"""

import os
import re
import sys

FOLDERS = ["simulation", "engine", "common/formats", "run_directory", "coordinator", "worker", "third_party/box2d"]
FUNCTIONS = ("exp", "exp2", "expm1", "log", "log2", "log10", "log1p", "pow", "sin", "cos", "tan", "sincos", "asin",
             "acos", "atan", "atan2", "sinh", "cosh", "tanh", "asinh", "acosh", "atanh", "hypot", "cbrt", "erf",
             "erfc", "lgamma", "tgamma")
# a call: the name (with f or l for float and long double), not a member (.log, ->exp) nor another namespace's
# (math::sin), nor part of a longer name, then an opening parenthesis
CALL = re.compile(r"(?<![\w.>:])(?:std::|::)?(" + "|".join(FUNCTIONS) + r")[fl]?\s*\(")
QUALIFIED_STD = re.compile(r"std::(" + "|".join(FUNCTIONS) + r")[fl]?\s*\(")
STRING = re.compile(r'"(?:[^"\\]|\\.)*"')


def code_of(line):
    """The line without its strings and its // comment."""
    line = STRING.sub('""', line)
    return line.split("//", 1)[0]


def calls(path):
    found = []
    in_block_comment = False
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            if in_block_comment:
                if "*/" not in line:
                    continue
                line = line.split("*/", 1)[1]
                in_block_comment = False
            if "/*" in line and "*/" not in line.split("/*", 1)[1]:
                line, in_block_comment = line.split("/*", 1)[0], True
            code = code_of(line)
            for match in list(CALL.finditer(code)) + list(QUALIFIED_STD.finditer(code)):
                found.append((number, match.group(0).rstrip("( "), line.strip()))
    return found


def main():
    if len(sys.argv) != 2:
        print(__doc__.strip().split("\n")[-1], file=sys.stderr)
        return 2
    source = sys.argv[1]
    problems = []
    files = 0
    for folder in FOLDERS:
        for directory, _, names in os.walk(os.path.join(source, folder)):
            for name in sorted(names):
                if not name.endswith((".cpp", ".h")):
                    continue
                files += 1
                path = os.path.join(directory, name)
                for number, call, text in calls(path):
                    problems.append(f"{os.path.relpath(path, source)}:{number}: {call}: {text}")
    if files == 0:
        print(f"check_own_math: no sources under {source}", file=sys.stderr)
        return 1
    if problems:
        print("the C library's transcendental functions are called on the path to a checkpoint; use math/'s "
              "(math/exponential.h, math/trigonometry.h):")
        print("\n".join(sorted(set(problems))))
        return 1
    print(f"check_own_math: {files} files of {', '.join(FOLDERS)} call none of the C library's transcendental "
          f"functions")
    return 0


if __name__ == "__main__":
    sys.exit(main())
