#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""No function of the project's own code is longer than its limit (issue 49).

One job per function: over 120 lines is a sign of two. The online side (online/, plant/runtime,
controller/runtime: the code that runs in the step) keeps every function to 80. Lengths are
Universal Ctags' start and end lines (`--fields=+ne`), end - start + 1, for every function,
method and lambda of the project's C and C++ files; tests/ and what the build generates (build*/,
out/: the lcm-gen messages) are left out.

KNOWN lists the functions still over the limit, each with its length when it was listed: one of
them may not grow past that length, and one that is now within the limit (or gone) must leave the
list, so that the list only shrinks. A function over the limit that is not on it fails the check.
An entry names a file and a function (overloads of one name in one file share it).

  tests/link/long_functions.py REPO_ROOT [--known FILE]
      prints what is over; exit 1 if anything is wrong. FILE replaces KNOWN (lines
      "PATH FUNCTION LENGTH"; the check's own fixture, tests/link/fixtures/long_functions, uses it).
"""
import json
import pathlib
import shutil
import subprocess
import sys

LIMIT = 120
ONLINE_LIMIT = 80
ONLINE = ("online/", "plant/runtime/", "controller/runtime/")
SOURCES = (".cpp", ".hpp", ".h", ".c")

# (file, function): its length in lines when listed. Empty since issue 49 split the last eight:
# a function over the limit is split, not listed.
KNOWN = {}


def read_known(path):
    known = {}
    for line in pathlib.Path(path).read_text().splitlines():
        if line.strip() and not line.startswith("#"):
            file, name, length = line.split()
            known[(file, name)] = int(length)
    return known


def limit_of(path):
    return ONLINE_LIMIT if path.startswith(ONLINE) else LIMIT


def own_sources(root):
    """The project's own C and C++ files, relative to root."""
    files = []
    for path in sorted(root.rglob("*")):
        rel = path.relative_to(root).as_posix()
        top = rel.split("/")[0]
        if path.suffix in SOURCES and not (top.startswith((".", "build")) or top in ("out", "tests")):
            files.append(rel)
    return files


def ctags_program():
    """Universal Ctags (Debian installs it as ctags-universal, and as ctags when no other is)."""
    for name in ("ctags-universal", "ctags"):
        program = shutil.which(name)
        if program:
            version = subprocess.run([program, "--version"], capture_output=True, text=True).stdout
            if "Universal Ctags" in version:
                return program
    sys.exit("long functions: Universal Ctags not found (Debian package universal-ctags)")


def functions(root, files):
    """(length, file, start, end, name) of every function ctags finds in files."""
    run = subprocess.run(
        [ctags_program(), "--fields=+ne", "--output-format=json", "--languages=C,C++",
         "--kinds-C++=f", "--kinds-C=f", "-L", "-", "-o", "-"],
        input="\n".join(files), cwd=root, capture_output=True, text=True, check=True)
    found = []
    for line in run.stdout.splitlines():
        tag = json.loads(line)
        if tag.get("_type") != "tag" or "end" not in tag:
            continue
        name = tag["name"]
        if name.startswith("__anon"):  # a lambda: named by where it is
            name = f"lambda in {tag.get('scope', '?')}"
        found.append((tag["end"] - tag["line"] + 1, tag["path"], tag["line"], tag["end"], name))
    return found


def main():
    args = sys.argv[1:]
    known = KNOWN
    if "--known" in args:
        at = args.index("--known")
        known = read_known(args[at + 1])
        del args[at:at + 2]
    root = pathlib.Path(args[0] if args else ".").resolve()
    files = own_sources(root)
    found = functions(root, files)
    bad = []
    over = 0
    seen = set()
    for length, path, start, end, name in sorted(found, key=lambda f: (f[1], f[2])):
        if length <= limit_of(path):
            continue
        over += 1
        where = f"{path}:{start}-{end}: {name}, {length} lines (limit {limit_of(path)})"
        listed = known.get((path, name))
        if listed is None:
            bad.append(f"{where}: over the limit; split it at its seams")
        elif length > listed:
            bad.append(f"{where}: grew past the {listed} lines it was listed with")
        else:
            print(f"{where}: known, listed at {listed}")
        seen.add((path, name))
    for (path, name), listed in sorted(known.items()):
        if (path, name) not in seen:
            bad.append(f"{path}: {name} is within its limit now (or gone): remove it from KNOWN "
                       f"in tests/link/long_functions.py")
    for line in bad:
        print(line)
    if bad:
        return 1
    print(f"long functions: {len(files)} files, {len(found)} functions, {over} over the limit, "
          f"each a known one")
    return 0


if __name__ == "__main__":
    sys.exit(main())
