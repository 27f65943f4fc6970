#!/usr/bin/env python3
"""Lists the includes that point up the layers of src/tsuchi (issue 14).

usage: /usr/bin/python3 scripts/check-layers.py [--quiet]

The layers, lowest first; a file may include its own folder and any folder of a lower layer,
never one above (folders on one layer may not include each other):

    comm -> core -> grid, particles -> shape -> material -> element, model -> solver -> io -> run -> app

io (files: the input and checkpoint readers, the frame and CSV writers) knows the model but not
the loop; run (the loop over time: recorders, output schedule, checkpoints, faults) drives the
solver and io. Every reported line is FILE:LINE, the include, and the two layers. Exit 0 if
nothing points up, 1 otherwise; a folder the list above does not name is an error (exit 2), so a
new folder must be placed here. ctest runs this script (test `layers`).
"""
import os
import re
import sys

REPO = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
LAYERS = [["comm"], ["core"], ["geometry", "grid", "particles"], ["shape"], ["material"], ["element", "model"], ["solver"],
          ["io"], ["run"], ["app"]]
RANK = {folder: i for i, layer in enumerate(LAYERS) for folder in layer}
INCLUDE = re.compile(r'^\s*#\s*include\s+"tsuchi/([a-z_]+)/[^"]+"')


def sources():
    """(folder, path) of every C++ source under src/tsuchi and app."""
    roots = [(os.path.join(REPO, "src", "tsuchi"), None), (os.path.join(REPO, "app"), "app")]
    for root, fixed in roots:
        for dirpath, _, names in os.walk(root):
            for name in sorted(names):
                if name.endswith((".hpp", ".cpp", ".h")):
                    folder = fixed or os.path.relpath(dirpath, root).split(os.sep)[0]
                    yield folder, os.path.join(dirpath, name)


def violations():
    found, unknown = [], set()
    for folder, path in sources():
        if folder not in RANK:
            unknown.add(folder)
            continue
        with open(path, encoding="utf-8") as f:
            for n, line in enumerate(f, 1):
                m = INCLUDE.match(line)
                if not m:
                    continue
                target = m.group(1)
                if target not in RANK:
                    unknown.add(target)
                elif target != folder and RANK[target] >= RANK[folder]:
                    found.append((os.path.relpath(path, REPO), n, line.strip(), folder, target))
    return found, unknown


def main(argv):
    found, unknown = violations()
    if unknown:
        print("folders not placed in a layer (edit LAYERS in scripts/check-layers.py): " + ", ".join(sorted(unknown)))
        return 2
    if "--quiet" not in argv:
        for path, n, line, folder, target in found:
            print(f"{path}:{n}: {line}    ({folder} includes {target}, "
                  f"{'the same layer' if RANK[target] == RANK[folder] else 'a higher layer'})")
    print(f"{len(found)} include(s) point up or across the layers")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
