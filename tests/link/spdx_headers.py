#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Every source file the project owns carries its licence as an SPDX tag in its header:

    // SPDX-License-Identifier: BSD-3-Clause      (C++, C: .cpp .hpp .c .h .cpp.in)
    # SPDX-License-Identifier: BSD-3-Clause       (Python, shell, CMake: .py .sh CMakeLists.txt
                                                   .cmake .cmake.in, scripts with a #! line)

in the comment block the file starts with (after a #! line; in a script whose usage text is its
header, after that text, so that `sed -n '2,Np' "$0"` still prints it). What others wrote is left
out (NOTICE: tests/fixtures/fmi2_schema/), and so are data files (tests/fuzz/corpus/) and the
link checks' fixture trees, whose line numbers their tests assert (tests/link/fixtures/).

  tests/link/spdx_headers.py REPO_ROOT          # names each owned source without the tag; exit 1
  tests/link/spdx_headers.py REPO_ROOT --fix    # adds the tag where it is missing
"""
import pathlib
import subprocess
import sys

LICENCE = "SPDX-License-Identifier: BSD-3-Clause"
NOT_OURS = ("tests/fixtures/fmi2_schema/", "tests/fuzz/corpus/", "tests/link/fixtures/")
SLASHES = (".cpp", ".hpp", ".c", ".h", ".cpp.in")
HASHES = (".py", ".sh", ".cmake", ".cmake.in")


def comment_marker(path, root):
    """'//' or '#' for a source file we own, None for anything else."""
    rel = path.relative_to(root).as_posix()
    if rel.startswith(NOT_OURS):
        return None
    if rel.endswith(SLASHES):
        return "//"
    if rel.endswith(HASHES) or path.name == "CMakeLists.txt":
        return "#"
    if "." not in path.name:
        with open(path, "rb") as f:
            if f.read(2) == b"#!":
                return "#"
    return None


def owned_files(root):
    """The tracked files (git ls-files); without git, every file outside build*/ and out/."""
    r = subprocess.run(["git", "-C", str(root), "ls-files", "-z"], capture_output=True)
    if r.returncode == 0:
        names = [n for n in r.stdout.decode().split("\0") if n]
        files = [root / n for n in names]
    else:
        skip = lambda p: any(part.startswith(("build", ".git")) or part == "out"
                             for part in p.relative_to(root).parts)
        files = [p for p in root.rglob("*") if p.is_file() and not skip(p)]
    for f in sorted(files):
        if f.is_file() and not f.is_symlink():
            marker = comment_marker(f, root)
            if marker:
                yield f, marker


def header_end(lines, marker):
    """Index of the first line after the file's opening comment block (a #! line, comments,
    blank lines; `#pragma once` in C++)."""
    for i, line in enumerate(lines):
        s = line.strip()
        if not s or s.startswith(marker) or (i == 0 and s.startswith("#!")) or \
                (marker == "//" and s == "#pragma once"):
            continue
        return i
    return len(lines)


def tag(marker):
    return f"{marker} {LICENCE}"


def has_tag(lines, marker):
    return tag(marker) in (line.rstrip("\n") for line in lines[:header_end(lines, marker)])


def add_tag(lines, marker):
    """The tag on the first line, or after a #! line and the header comment block under it."""
    if lines and lines[0].startswith("#!"):
        at = header_end(lines, marker)
        while at > 1 and not lines[at - 1].strip():
            at -= 1  # before the blank lines that end the header
        return lines[:at] + [tag(marker) + "\n"] + lines[at:]
    return [tag(marker) + "\n"] + lines


def main():
    root = pathlib.Path(sys.argv[1]).resolve()
    fix = "--fix" in sys.argv[2:]
    missing, checked = [], 0
    for f, marker in owned_files(root):
        checked += 1
        text = f.read_text(encoding="utf-8")
        lines = text.splitlines(keepends=True)
        if has_tag(lines, marker):
            continue
        if fix:
            f.write_text("".join(add_tag(lines, marker)), encoding="utf-8")
            print(f"added: {f.relative_to(root)}")
        else:
            missing.append(f.relative_to(root).as_posix())
    for m in missing:
        print(f"{m}: no '{LICENCE}' line in its header (add it: tests/link/spdx_headers.py . --fix)")
    if missing:
        print(f"spdx headers: {len(missing)} of {checked} owned sources without the tag")
        return 1
    print(f"spdx headers: all {checked} owned sources carry {LICENCE}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
