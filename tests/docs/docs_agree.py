#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Docs that agree with the program (issue 55, 5): in README.md and doc/*.md

  - every relative link resolves: its file exists, and its #anchor is a heading of that file
    (GitHub's slugs); a page of doc/ links nothing outside the repository;
  - every `flexloop CMD [SUB] ... --option` written in a code span or block is an option of that
    command (read from `flexloop CMD --help`);
  - in `flexloop linearise|analyse`, `-i/--input` and `-O/--output` name channels (`pos:x.2`), and
    no other command's `-o/--output` is given a channel;
  - every README "Section" that a page of doc/ cites is a heading of README.md;
  - every TOML example (```toml) parses, and a whole model, scene or U.toml is accepted by the
    program (`linearise`, `build`, `campaign plan`);
  - doc/lcm_messages.md lists each message's fields as msgs/*.lcm declares them, in that order.

  tests/docs/docs_agree.py FLEXLOOP REPO_ROOT   # prints each disagreement; exit 1 if any
"""
import pathlib
import re
import subprocess
import sys
import tempfile
import tomllib

LINK = re.compile(r"\[[^\]]*\]\(([^)\s]+)\)")
HEADING = re.compile(r"^(#{1,6})\s+(.*?)\s*#*\s*$")
FENCE = re.compile(r"^\s*```")
INLINE_CODE = re.compile(r"`([^`\n]+)`")
README_SECTION = re.compile(r'README[\'’]?s?,? "([^"]+)"')


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
                if re.match(r"^[a-z]+:", target):  # http:, https:, mailto:
                    if f.parent.name == "doc":
                        problems.append(f"{f.relative_to(root)}:{number}: link to {target}: "
                                        f"doc/ points only inside the repository")
                    continue
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
                    for problem in channel_or_file(path, words[used:]):
                        problems.append(f"{f.relative_to(root)}:{number}: flexloop "
                                        f"{' '.join(path)}: {problem}")
    return problems


CHANNEL = re.compile(r"^\[?(pos|vel|acc|force|stress|reaction):\S+")


def channel_or_file(path, words):
    """`--output` is a channel in linearise and analyse (their file is -o/--out, their folder
    --out-dir) and a file everywhere else: each value written after it must be the right kind."""
    channel_options = {"-i", "--input", "-O", "--output"} if path in (("linearise",),
                                                                     ("analyse",)) else set()
    for option, value in zip(words, words[1:]):
        option = option.lstrip("[")
        if value.startswith(("-", "[", "NAME", "...")):
            continue  # a synopsis placeholder or the next option
        if option in channel_options and not CHANNEL.match(value):
            yield f"{option} names a channel (pos:x.2, stress:e1.4, ...), not {value}"
        elif option in {"-o", "--output", "--out"} and option not in channel_options and \
                CHANNEL.match(value):
            yield f"{option} is the file to write, not the channel {value}"


def check_readme_sections(root):
    # A section is cited by its heading's text, or the start of it ("Scenes shipped" for
    # "Scenes shipped (`tools/scenes/`)").
    readme = [slug(h) for h in re.findall(r"^#{1,6}\s+(.*?)\s*$",
                                          (root / "README.md").read_text(encoding="utf-8"), re.M)]
    problems = []
    for page in sorted((root / "doc").glob("*.md")):
        for number, line in enumerate(page.read_text(encoding="utf-8").splitlines(), 1):
            for section in README_SECTION.findall(line):
                if not any(h.startswith(slug(section)) for h in readme):
                    problems.append(f"{page.relative_to(root)}:{number}: README has no section "
                                    f"\"{section}\"")
    return problems


def toml_blocks(path):
    """(line number, text) of each ```toml block."""
    block, start = None, 0
    for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
        if block is None and re.match(r"^\s*```toml\s*$", line):
            block, start = [], number + 1
        elif block is not None and FENCE.match(line):
            yield start, "\n".join(block) + "\n"
            block = None
        elif block is not None:
            block.append(line)


def program_accepts(flexloop, root, text, work):
    """What the program says of a whole model, scene or U.toml (None: accepted, or not whole).
    A scene is placed in a folder beside links to tools/models and tools/controllers, so that
    its relative paths (`../models/...`) resolve as from tools/scenes/."""
    doc = tomllib.loads(text)
    scenes = work / "scenes"
    scenes.mkdir(exist_ok=True)
    for folder in ("models", "controllers"):
        if not (work / folder).exists():
            (work / folder).symlink_to(root / "tools" / folder)
    example = scenes / "example.toml"
    example.write_text(text, encoding="utf-8")
    if "superelement" in doc:
        return None  # it names the user's FE files, which the repository does not hold: parsed
    if "model" in doc and "node" in doc:
        command = ["linearise", str(example), "-o", str(work / "lin.json")]
    elif "scene" in doc:
        command = ["build", str(example), "-o", str(work / "loop.json")]
    elif "parameter" in doc:
        command = ["campaign", "plan", str(root / "tools/scenes/metrology_frame.toml"), "-u",
                   str(example), "-n", "2", "-o", str(work / "plan.json")]
    else:
        return None  # a table or two of a larger file: parsed above, not run
    r = subprocess.run([flexloop, *command], capture_output=True, text=True)
    if r.returncode != 0:
        return f"flexloop {command[0]} refuses it: {(r.stderr or r.stdout).strip()[-300:]}"
    return None


def check_toml_examples(flexloop, root, files):
    problems = []
    with tempfile.TemporaryDirectory() as tmp:
        for f in files:
            for number, text in toml_blocks(f):
                where = f"{f.relative_to(root)}:{number}"
                try:
                    problem = program_accepts(flexloop, root, text, pathlib.Path(tmp))
                except tomllib.TOMLDecodeError as e:
                    problem = f"not TOML: {e}"
                if problem:
                    problems.append(f"{where}: the TOML example: {problem}")
    return problems


def lcm_fields(path):
    """The fields of an .lcm struct, in declaration order (`sensors[n_sensors]` as `sensors`)."""
    text = re.sub(r"//[^\n]*", "", path.read_text(encoding="utf-8"))
    body = text[text.index("{") + 1:text.rindex("}")]
    return [m.group(1) for m in re.finditer(r"^\s*\w+\s+(\w+)\s*(?:\[[^\]]*\])?\s*;", body, re.M)]


def check_lcm_messages(root):
    """Each row `| \`NAME\` | fields |` of doc/lcm_messages.md: the identifiers in code spans of its
    fields column, first occurrences in order, are the struct's fields."""
    problems = []
    page = root / "doc" / "lcm_messages.md"
    seen = set()
    for number, line in enumerate(page.read_text(encoding="utf-8").splitlines(), 1):
        m = re.match(r"^\|\s*`(\w+_t)`\s*\|(.*)\|\s*$", line)
        if not m:
            continue
        name, declared = m.group(1), lcm_fields(root / "msgs" / f"{m.group(1)}.lcm")
        seen.add(name)
        written = []
        for span in INLINE_CODE.findall(m.group(2)):
            field = re.match(r"^(\w+)(\[[^\]]*\])?$", span)
            if field and field.group(1) not in written:
                written.append(field.group(1))
        if written != declared:
            problems.append(f"doc/lcm_messages.md:{number}: {name} lists {written}, "
                            f"msgs/{name}.lcm declares {declared}")
    for lcm in sorted((root / "msgs").glob("*.lcm")):
        if lcm.stem not in seen:
            problems.append(f"doc/lcm_messages.md: no row for {lcm.stem} (msgs/{lcm.name})")
    return problems


def main():
    flexloop, root = sys.argv[1], pathlib.Path(sys.argv[2]).resolve()
    files = [root / "README.md", *sorted((root / "doc").glob("*.md"))]
    problems = (check_links(root, files) + check_commands(root, files, Commands(flexloop)) +
                check_readme_sections(root) + check_toml_examples(flexloop, root, files) +
                check_lcm_messages(root))
    for p in problems:
        print(p)
    if problems:
        print(f"docs agree: {len(problems)} disagreements")
        return 1
    print(f"docs agree: {len(files)} files, every link, command option, channel, README section, "
          f"TOML example and message field found")
    return 0


if __name__ == "__main__":
    sys.exit(main())
