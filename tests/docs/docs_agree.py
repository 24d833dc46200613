#!/usr/bin/env python3
"""Docs that agree with the program (issue 55, 5): in README.md and doc/*.md

  - every relative link resolves: its file exists, and its #anchor is a heading of that file
    (GitHub's slugs);
  - every `flexloop CMD [SUB] ... --option` written in a code span or block is an option of that
    command (read from `flexloop CMD --help`);
  - every README "Section" that doc/design.md cites is a heading of README.md.

  tests/docs/docs_agree.py FLEXLOOP REPO_ROOT   # prints each disagreement; exit 1 if any
"""
import pathlib
import re
import subprocess
import sys

LINK = re.compile(r"\[[^\]]*\]\(([^)\s]+)\)")
HEADING = re.compile(r"^(#{1,6})\s+(.*?)\s*#*\s*$")
FENCE = re.compile(r"^\s*```")
INLINE_CODE = re.compile(r"`([^`\n]+)`")
README_SECTION = re.compile(r'README[\'’]?s? "([^"]+)"')


def slug(heading):
    """GitHub's anchor of a heading: lower case, punctuation dropped, spaces to hyphens."""
    text = heading.replace("`", "").replace("*", "")
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", text)  # a link in a heading: its text
    text = text.strip().lower()
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors(path):
    seen, out = {}, set()
    in_fence = False
    for line in path.read_text(encoding="utf-8").splitlines():
        if FENCE.match(line):
            in_fence = not in_fence
            continue
        m = None if in_fence else HEADING.match(line)
        if m:
            base = slug(m.group(2))
            n = seen.get(base, 0)
            seen[base] = n + 1
            out.add(base if n == 0 else f"{base}-{n}")
    return out


def check_links(root, files):
    problems = []
    for f in files:
        text = f.read_text(encoding="utf-8")
        for number, line in enumerate(text.splitlines(), 1):
            for target in LINK.findall(line):
                if re.match(r"^[a-z]+:", target):
                    continue  # http:, https:, mailto:
                file_part, _, anchor = target.partition("#")
                dest = f if not file_part else (f.parent / file_part).resolve()
                where = f"{f.relative_to(root)}:{number}"
                if not dest.exists():
                    problems.append(f"{where}: link to {target}: no such file")
                elif anchor and dest.suffix == ".md" and anchor not in anchors(dest):
                    problems.append(f"{where}: link to {target}: no heading with that anchor")
                elif root not in dest.parents and dest != root:
                    problems.append(f"{where}: link to {target}: outside the repository")
    return problems


def code_texts(path):
    """(line number, text) of every code block line and inline code span."""
    in_fence = False
    for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        if FENCE.match(line):
            in_fence = not in_fence
            continue
        if in_fence:
            yield number, line
        else:
            for span in INLINE_CODE.findall(line):
                yield number, span


class Commands:
    """The options of each `flexloop` command path, from its --help."""

    def __init__(self, flexloop):
        self.flexloop = flexloop
        self.cache = {}

    def help(self, path):
        if path not in self.cache:
            r = subprocess.run([self.flexloop, *path, "--help"], capture_output=True, text=True)
            self.cache[path] = r.stdout if r.returncode == 0 else None
        return self.cache[path]

    def subcommands(self, path):
        text = self.help(path) or ""
        part = re.split(r"^Subcommands:", text, maxsplit=1, flags=re.M)
        if len(part) < 2:
            return set()
        return set(re.findall(r"^\s{2}(\S+)", part[1], re.M))

    def options(self, path):
        return set(re.findall(r"(--[A-Za-z0-9][\w-]*)", self.help(path) or ""))


def command_uses(text):
    """Each `flexloop ...` in a line: the words after it up to a shell separator (a word may be
    an alternation, `timer|pingpong|shm`)."""
    for m in re.finditer(r"(?:^|[\s(`$])flexloop((?:\s+[^\s;&><)`#]+)+)", text):
        words = []
        for w in m.group(1).split():
            if w == "|" or w.startswith("#"):
                break
            words.append(w)
        yield words


def command_paths(words, commands):
    """The command paths the words name (several for an alternation) and how many words."""
    paths, used = [()], 0
    for w in words:
        parts = w.split("|")
        if not all(p in commands.subcommands(paths[0]) for p in parts):
            break
        paths = [path + (p,) for path in paths for p in parts]
        used += 1
    return ([] if used == 0 else paths), used


# Docs about one command: a bare `--option` there is one of its options (or its subcommands').
# (The campaign's Slurm pages quote sbatch's options, logs.md and plant_fmu.md other programs':
# not listed.)
COMMAND_DOCS = {"tradeoff.md": ("tradeoff",)}


def all_options(commands, path):
    out = set(commands.options(path))
    for sub in commands.subcommands(path):
        out |= commands.options(path + (sub,))
    return out


def check_bare_options(root, f, commands):
    if f.name not in COMMAND_DOCS:
        return []
    known = all_options(commands, COMMAND_DOCS[f.name]) | {"--help"}
    problems = []
    for number, text in code_texts(f):
        if "flexloop" in text:
            continue  # a command line: checked with its own command
        m = re.fullmatch(r"(--[A-Za-z0-9][\w-]*)(?:[ =].*)?", text.strip())
        if m and m.group(1) not in known:
            problems.append(f"{f.relative_to(root)}:{number}: {m.group(1)} is no option of "
                            f"flexloop {' '.join(COMMAND_DOCS[f.name])}")
    return problems


def check_commands(root, files, commands):
    problems = []
    for f in files:
        problems += check_bare_options(root, f, commands)
        for number, text in code_texts(f):
            for words in command_uses(text):
                paths, used = command_paths(words, commands)
                for path in paths:
                    for w in words[used:]:
                        opt = re.match(r"^\[?(--[A-Za-z0-9][\w-]*)", w)
                        if opt and opt.group(1) not in commands.options(path) | {"--help"}:
                            problems.append(f"{f.relative_to(root)}:{number}: flexloop "
                                            f"{' '.join(path)} has no option {opt.group(1)}")
    return problems


def check_readme_sections(root):
    # A section is cited by its heading's text, or the start of it ("Scenes shipped" for
    # "Scenes shipped (`tools/scenes/`)").
    readme = [slug(h) for h in re.findall(r"^#{1,6}\s+(.*?)\s*$",
                                          (root / "README.md").read_text(encoding="utf-8"), re.M)]
    problems = []
    design = root / "doc" / "design.md"
    for number, line in enumerate(design.read_text(encoding="utf-8").splitlines(), 1):
        for section in README_SECTION.findall(line):
            if not any(h.startswith(slug(section)) for h in readme):
                problems.append(f"doc/design.md:{number}: README has no section \"{section}\"")
    return problems


def main():
    flexloop, root = sys.argv[1], pathlib.Path(sys.argv[2]).resolve()
    files = [root / "README.md", *sorted((root / "doc").glob("*.md"))]
    problems = (check_links(root, files) + check_commands(root, files, Commands(flexloop)) +
                check_readme_sections(root))
    for p in problems:
        print(p)
    if problems:
        print(f"docs agree: {len(problems)} disagreements")
        return 1
    print(f"docs agree: {len(files)} files, every link, command option and README section found")
    return 0


if __name__ == "__main__":
    sys.exit(main())
