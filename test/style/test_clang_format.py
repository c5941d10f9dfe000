#!/usr/bin/python3
"""The C++ sources are formatted as the repository's .clang-format says: every *.cpp, *.h and
*.hpp under src/, include/ and test/ passes `clang-format --dry-run --Werror`. Nothing is
skipped: a missing clang-format is a failure, not a skip.
Run directly, or with --gtest_output=xml:FILE (as scripts/test runs the gtests) for a JUnit file."""
import pathlib
import shutil
import subprocess
import sys
import unittest

REPO = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "test" / "docs"))
from test_docs import main  # noqa: E402  (the runner and JUnit output the script tests share)

SOURCE_DIRS = ("src", "include", "test")
SUFFIXES = (".cpp", ".h", ".hpp")


def cpp_sources():
    files = []
    for top in SOURCE_DIRS:
        files += [p for p in (REPO / top).rglob("*") if p.suffix in SUFFIXES and p.is_file()]
    return sorted(files)


class ClangFormat(unittest.TestCase):
    def test_every_cpp_source_is_formatted(self):
        tool = shutil.which("clang-format")
        self.assertIsNotNone(tool, "clang-format is not installed (Debian package clang-format)")
        files = cpp_sources()
        self.assertGreater(len(files), 100, "found too few C++ sources: wrong repository root?")
        run = subprocess.run([tool, "--dry-run", "--Werror", f"--style=file:{REPO / '.clang-format'}"]
                             + [str(f) for f in files], capture_output=True, text=True)
        unformatted = sorted({line.split(":", 1)[0] for line in run.stderr.splitlines() if ": error:" in line})
        self.assertEqual(run.returncode, 0,
                         f"{len(unformatted)} of {len(files)} files are not clang-format clean "
                         f"(fix with clang-format -i):\n" + "\n".join(unformatted) + "\n" + run.stderr[-2000:])

    def test_finds_sources_in_every_folder(self):
        for top in SOURCE_DIRS:
            self.assertTrue(any(f.is_relative_to(REPO / top) for f in cpp_sources()), top)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:], sys.modules[__name__]))
