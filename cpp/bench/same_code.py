#!/usr/bin/python3
"""Whether two builds of the library compiled the same instructions: every object of the library
(ifsforge and ifsforge_vdb) in AFTER against the object of the same source in BEFORE, function
by function, from `objdump -d -r`. What only the layout decides is left out: the order of the
functions and sections, addresses and offsets to other functions or to data, the symbol objdump
guesses for a call (its relocation names the callee) and the padding between blocks. A change of
the build that should not change the code (a precompiled header, an include order) is checked
with it (docs/developer.md, "Compile time").

    cpp/bench/same_code.py BEFORE_BUILD AFTER_BUILD   # exit status 1 when a function differs
"""
import argparse
import re
import subprocess
import sys
from pathlib import Path

LIBRARY = ("cpp/CMakeFiles/ifsforge.dir", "cpp/CMakeFiles/ifsforge_vdb.dir")
PADDING = re.compile(r"(nop|xchg\s+%ax,%ax|data16|cs nop)")
CLONE = re.compile(r"\.(isra|constprop|part)\.\d+|\.cold\b|\.LC\d+")


def functions(path):
    """{function: its instructions, layout aside} of an object."""
    text = subprocess.run(["objdump", "-d", "-r", "--no-show-raw-insn", str(path)],
                          capture_output=True, text=True, check=True).stdout
    out, name = {}, None
    for line in text.splitlines():
        head = re.match(r"^[0-9a-f]+ <(.+)>:$", line)
        if head:
            name = head.group(1)
            out[name] = []
            continue
        if name is None or not line.strip() or line.startswith("Disassembly"):
            continue
        line = re.sub(r"^\s*[0-9a-f]+:\s*", "", line).strip()  # the instruction's own address
        if PADDING.match(line):
            continue
        line = re.sub(r"\b[0-9a-f]+ <", "<", line)  # a branch target's address
        # A target in another function (a .cold part, a local helper) moves with the layout.
        line = re.sub(r"<([^>+]+)(\+0x[0-9a-f]+)?>", lambda m: m.group(0) if m.group(1) == name else "<T>", line)
        line = re.sub(r"^(call\s+)<.*>", r"\1<T>", line)  # an unlinked call: its relocation names the callee
        line = re.sub(r"(\.text[.\w]*)\+0x[0-9a-f]+", r"\1+X", line)
        line = re.sub(r"-?0x[0-9a-f]+\(%rip\)", "X(%rip)", line)
        out[name].append(CLONE.sub("", line))
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("before", type=Path, help="a build folder, e.g. one configured with -DCMAKE_DISABLE_PRECOMPILE_HEADERS=ON")
    parser.add_argument("after", type=Path, help="the build folder to compare with it")
    args = parser.parse_args()
    before, after = args.before, args.after
    same, differ = 0, 0
    for folder in LIBRARY:
        for obj in sorted((after / folder).glob("src/**/*.o")):
            source = obj.relative_to(after / folder)
            old = next((before / f / source for f in LIBRARY if (before / f / source).exists()), None)
            if old is None:
                print(f"{source}: not in {before}")
                differ += 1
                continue
            a, b = functions(old), functions(obj)
            bad = [n for n in set(a) | set(b) if a.get(n) != b.get(n)]
            if bad:
                differ += 1
                print(f"{source}: {len(bad)} of {len(set(a) | set(b))} functions differ, e.g. {sorted(bad)[0][:100]}")
            else:
                same += 1
    print(f"{same} objects the same instructions, {differ} not")
    sys.exit(1 if differ else 0)


if __name__ == "__main__":
    main()
