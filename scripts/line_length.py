#!/usr/bin/env python3
"""Fails when a line of the repository's C++ runs past .clang-format's ColumnLimit (110 characters).

    scripts/line_length.py    lists each long line as path:line: length; exits 1 when there is one

A line that holds part of a raw string literal (a test's XML or URDF) is data, which clang-format leaves as
it is, and is not counted. `clang-format -i --lines=N:N FILE` wraps a line the check names
(`apt-get install clang-format`).
"""
import pathlib
import re
import subprocess
import sys

REPO = pathlib.Path(__file__).resolve().parent.parent
LIMIT = int(re.search(r"ColumnLimit:\s*(\d+)", (REPO / ".clang-format").read_text()).group(1))
RAW_OPEN = re.compile(r'R"([^()\\ ]{0,16})\(')


def long_lines(path):
    """(line number, length) of each line past the limit that holds no raw string."""
    closing = None  # the end of the raw string a line is inside
    for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        raw = closing is not None
        rest = line
        while True:
            if closing:
                end = rest.find(closing)
                if end < 0:
                    break
                rest, closing = rest[end + len(closing):], None
            opening = RAW_OPEN.search(rest)
            if not opening:
                break
            raw, closing = True, ")" + opening.group(1) + '"'
            rest = rest[opening.end():]
        if len(line) > LIMIT and not raw:
            yield number, len(line)


def cpp_files():
    """The repository's C++ files: git's list, or outside a git clone every one but the build's."""
    listed = subprocess.run(["git", "-C", str(REPO), "ls-files", "*.cpp", "*.h"], capture_output=True,
                            text=True)
    if listed.returncode == 0:
        return listed.stdout.split()
    skipped = {"build", "devel", "install", ".git"}
    return sorted(str(path.relative_to(REPO)) for path in REPO.rglob("*") if path.suffix in (".cpp", ".h")
                  and not skipped.intersection(path.relative_to(REPO).parts))


def main():
    files = cpp_files()
    if not files:
        print(f"line_length.py: no C++ file found under {REPO}", file=sys.stderr)
        return 1
    found = 0
    for name in files:
        for number, length in long_lines(REPO / name):
            print(f"{name}:{number}: {length} characters (limit {LIMIT})")
            found += 1
    print(f"{found} lines past {LIMIT} characters in {len(files)} C++ files")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
