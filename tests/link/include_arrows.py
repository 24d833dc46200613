#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""The include arrows between folders go only where doc/design.md §2 allows them.

Every `#include "folder/..."` in the project's own code (not tests/, which may include anything)
is an arrow from the including file's folder to the included file's folder. Each folder may
include only the folders listed for it below: lower floors, and on floor 4 the assemblies below
it on the same side. The online side (plant/runtime, controller/runtime, online/*) never
includes the model, the parsers, the analysis, the design or the offline assemblies.
cmake/OnlineSplit.cmake and tests/link/online_links.sh check the same split for what links.

  tests/link/include_arrows.py REPO_ROOT    # prints each arrow not allowed; exit 1 if any
"""
import pathlib
import re
import sys

# Floors (doc/design.md §2): 0 numeric, common; 1 msgs, rt; 2 artefact; 3 the mathematics, offline
# (plant/model, plant/lti, controller/design) and online (plant/runtime, controller/runtime);
# 4 the assemblies; 5 tools.
ALLOWED = {
    "numeric": set(),
    "common": {"numeric"},
    "msgs": set(),
    "rt": {"numeric", "common", "msgs"},
    "artefact": {"numeric", "common"},
    "plant/superelement": {"numeric", "common"},
    "plant/model": {"numeric", "common", "plant/superelement"},
    "plant/lti": {"numeric", "common", "plant/model"},
    "controller/design": {"numeric", "common", "plant/model", "plant/lti"},
    "plant/runtime": {"numeric", "common", "artefact"},
    "controller/runtime": {"numeric", "common", "artefact"},
    # A controller FMU is a LoopController and the FMU alternative of the runtime's
    # controller_from_artefact.hpp (fmu_from_artefact.hpp); the runtime never includes the loader.
    "controller/fmu": {"numeric", "common", "artefact", "controller/runtime"},
    "online/sim": {"numeric", "common", "artefact", "plant/runtime", "controller/runtime", "controller/fmu"},
    # controller/fmu: only the controller process's loop (loop_controller.hpp, for
    # controller_loop.cpp, a library apart: the plant process links no FMU loader).
    "online/loop": {"numeric", "common", "msgs", "rt", "artefact", "plant/runtime",
                    "controller/runtime", "controller/fmu", "online/sim"},
    "online/hil": {"numeric", "common", "msgs", "rt", "artefact", "plant/runtime",
                   "controller/runtime", "controller/fmu", "online/sim", "online/loop"},
    # The plant FMU's library: the artefact's plant and hardware behind the FMI calls.
    "online/plant_fmu": {"numeric", "common", "artefact", "plant/runtime", "controller/runtime",
                         "online/sim"},
    "offline/report": {"numeric", "common", "msgs", "rt", "plant/model", "plant/lti"},
    "offline/scene": {"numeric", "common", "artefact", "plant/model", "plant/lti",
                      "controller/design", "controller/runtime"},
    "offline/pipeline": {"numeric", "common", "artefact", "plant/model", "plant/lti",
                         "controller/design", "plant/runtime", "controller/runtime",
                         "controller/fmu", "offline/scene", "offline/report", "online/plant_fmu"},
    # Campaigns: what the pipeline may include, and the pipeline; online/sim for --simulate
    # (a sample's loop run by `flexloop sim`'s code, as offline/study times the online kernels);
    # plant/superelement for the plan's one reduction that its shards read.
    "offline/campaign": {"numeric", "common", "artefact", "plant/model", "plant/superelement",
                         "plant/lti",
                         "controller/design", "plant/runtime", "controller/runtime",
                         "controller/fmu", "offline/scene", "offline/report", "online/plant_fmu",
                         "offline/pipeline", "online/sim"},
    # The study times the online kernels (it uses them; they never use it).
    "offline/study": {"numeric", "common", "artefact", "plant/model", "plant/lti",
                      "controller/design", "plant/runtime", "controller/runtime", "online/sim",
                      "offline/scene", "offline/report"},
}
TOOLS_MAY_NOT = {"tests"}
SOURCES = (".cpp", ".hpp", ".h", ".c")


def folder_of(path):
    """The folder a repository path belongs to, as ALLOWED names it."""
    parts = path.split("/")
    if parts[0] in ("plant", "controller", "offline", "online") and len(parts) > 2:
        return "/".join(parts[:2])
    return parts[0]


def main():
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".").resolve()
    known = set(ALLOWED) | {"tools", "tests"}
    bad = []
    files = 0
    for path in sorted(root.rglob("*")):
        rel = path.relative_to(root).as_posix()
        if path.suffix not in SOURCES or rel.startswith(("build/", "out/", ".")):
            continue
        source = folder_of(rel)
        if source == "tests":
            continue
        files += 1
        if source not in known:
            bad.append(f"{rel}: folder '{source}' has no rule in tests/link/include_arrows.py")
            continue
        for number, line in enumerate(path.read_text(errors="replace").splitlines(), start=1):
            m = re.match(r'\s*#\s*include\s+"([^"]+)"', line)
            if not m or "/" not in m.group(1):
                continue  # a file beside this one (the external controller's C headers)
            target = folder_of(m.group(1))
            if target == source:
                continue
            allowed = (known - TOOLS_MAY_NOT) if source == "tools" else ALLOWED[source]
            if target not in allowed:
                bad.append(f"{rel}:{number}: {source} -> {target} ({m.group(1)}) is not an "
                           f"allowed arrow")
    for b in bad:
        print(b)
    if not bad:
        print(f"include arrows: {files} files, every arrow allowed")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
