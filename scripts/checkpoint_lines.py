#!/usr/bin/env python3
"""Issue 41's yardstick for "checkpoint and resume code": the non-blank, non-comment lines
of every non-test Rust item (a top-level fn, struct, enum or trait, or a method) whose
text matches a checkpoint/resume keyword, at a git revision. A heuristic (an item that
only mentions a checkpoint counts whole), but the same at every revision, so two counts
compare. Usage: scripts/checkpoint_lines.py REV (e.g. 18580cb~1, before the trainer
split, and HEAD)."""
import re, subprocess, sys
rev = sys.argv[1]
KW = re.compile(r'checkpoint|resume|safetensors|LearnerState|learner_state|from_state|\bload\b|save_|Checkpoint|Modules|restore', re.I)
files = subprocess.run(['git','ls-tree','-r','--name-only',rev,'crates'],capture_output=True,text=True).stdout.split()
files = [f for f in files if f.endswith('.rs') and '/tests/' not in f and '/benches/' not in f]
total = 0; per = {}
for f in files:
    src = subprocess.run(['git','show',f'{rev}:{f}'],capture_output=True,text=True).stdout
    # drop #[cfg(test)] mod tests { ... } at the end
    m = re.search(r'\n#\[cfg\(test\)\]\s*\nmod tests', src)
    if m: src = src[:m.start()]
    lines = src.split('\n')
    # find items: lines starting (possibly indented <=4) with fn/struct/enum/impl headers
    i = 0; n = len(lines)
    while i < n:
        l = lines[i]
        if re.match(r'^( {0,4})(pub(\([^)]*\))? )?(async )?(fn|struct|enum|impl|trait) ', l) and not l.strip().startswith('impl') or re.match(r'^( {4})(pub(\([^)]*\))? )?fn ', l):
            # item extends until braces balance
            depth = 0; j = i; started = False
            while j < n:
                depth += lines[j].count('{') - lines[j].count('}')
                if '{' in lines[j]: started = True
                if started and depth <= 0: break
                if not started and lines[j].rstrip().endswith(';'): break
                j += 1
            text = '\n'.join(lines[i:j+1])
            code = [x for x in lines[i:j+1] if x.strip() and not x.strip().startswith('//')]
            if KW.search(text):
                per[f] = per.get(f,0) + len(code); total += len(code)
            i = j + 1
        else:
            i += 1
for f,c in sorted(per.items(), key=lambda x:-x[1])[:25]:
    print(f'{c:5d} {f}')
print('files', len(per), 'total', total)
