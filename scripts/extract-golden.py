#!/usr/bin/env python3
"""Extract every Tx:/Rx: capture of seed 003 (LinRS manual) with its section.

Output (tests/golden/seed003-captures.txt): one capture per line,
  <section> <line-in-seed> <Tx|Rx> <hex bytes> [; comment]
The vectors come from the manual, never from the code under test; the test
suite checks this file against the seed when the seed is present.
"""
import re
import sys

seed, out = sys.argv[1], sys.argv[2]
heading = re.compile(r'^\s*(?:#+\s*)?(?:\*\*)?\s*(\d+(?:\.\d+)*)\s+[A-Z][A-Za-z]')
capture = re.compile(r'^\s*(Tx|Rx):\s*((?:[0-9A-Fa-f]{2}\s*|\*\*\s*)+)(.*)$')
section = '0'
rows = []
with open(seed, encoding='utf-8') as f:
    for no, line in enumerate(f, 1):
        m = heading.match(line)
        if m and not line.lstrip().startswith('|'):
            section = m.group(1)
            continue
        m = capture.match(line)
        if not m:
            continue
        hexpart = m.group(2).replace('**', ' ')
        data = ' '.join(b.upper() for b in hexpart.split())
        comment = m.group(3).strip().lstrip(';').strip()
        rows.append(f'{section} {no} {m.group(1)} {data}' + (f' ; {comment}' if comment else ''))
with open(out, 'w', encoding='utf-8') as f:
    f.write('# Tx/Rx captures of seed 003 (LinRS manual V3.6), extracted by scripts/extract-golden.py\n')
    f.write('# section line direction bytes [; comment]\n')
    f.write('\n'.join(rows) + '\n')
print(f'{len(rows)} captures')
