#!/usr/bin/env bash
# The README's example session is what the commands print: every `$ command` of the indented
# block under "## Example session" runs in a scratch folder beside a link to data/ (surfkit is
# the built tool), and its output (stdout and stderr) must match the lines that follow it, where
# a line "..." stands for any number of lines and "..." inside a line for any text.
set -u
bin=$1 src=$2 shared=$3 tmp=$4
rm -rf "$tmp"; mkdir -p "$tmp"
ln -s "$src/data" "$tmp/data"
python3 - "$bin" "$src/README.md" "$tmp" <<'PY'
import re, subprocess, sys
bin, readme, tmp = sys.argv[1:]
text = open(readme).read()
block = text.split("## Example session", 1)[1].split("\n## ", 1)[0]
lines = [l[4:] for l in block.split("\n") if l.startswith("    ")]
cmds = []
for l in lines:
    if l.startswith("$ "):
        cmds.append((l[2:], []))
    elif cmds:
        cmds[-1][1].append(l)
script = "rc=0\n"
for k, (c, _) in enumerate(cmds):
    c = re.sub(r"(^|&& |\| )surfkit ", lambda m: m.group(1) + '"$SK" ', c)
    # the marker, then $? restored to the previous command's status (for `echo $?`)
    script += f'echo "@@{k}"; (exit $rc); {c} 2>&1; rc=$?\n'
import os
env = dict(os.environ, SK=bin)   # the caller's environment (sanitizer options) plus the tool
out = subprocess.run(["bash", "-c", script], cwd=tmp, env=env, capture_output=True,
                     text=True).stdout
parts = re.split(r"^@@(\d+)\n", out, flags=re.M)
got = {int(parts[i]): parts[i + 1] for i in range(1, len(parts) - 1, 2)}
bad = 0
for k, (c, want) in enumerate(cmds):
    rx = ""
    for w in want:
        if w.strip() == "...":
            rx += r"(?:[^\n]*\n)*?"
        else:
            rx += ".*".join(re.escape(p) for p in w.split("...")) + r"\n"
    if not re.fullmatch(rx, got.get(k, "")):
        bad += 1
        print(f"FAIL: `{c}` printed:\n{got.get(k, '(nothing)')}--- the README says:\n" + "\n".join(want))
if bad:
    sys.exit(1)
print(f"readme: {len(cmds)} commands print what the README says")
PY
