#!/usr/bin/env python3
# Where concepts live (issue 49): lines of the binary (src/), library files that write out
# outcome kinds, Result<_, String> in library code, SQL state literals beside JobState, and
# what src/ still does that a library should (Slurm polling, sleeping, status gathering,
# import). Library code is crates/*/src outside #[cfg(test)] modules and // comments.
# Usage: python3 scripts/measure-concepts.py [ROOT]   (ROOT: a checkout, default .)
import os, re, sys
root = sys.argv[1] if len(sys.argv) > 1 else '.'
def rs(d):
    for r, _, fs in os.walk(os.path.join(root, d)):
        for f in fs:
            if f.endswith('.rs'): yield os.path.join(r, f)
def code(p):
    out = []
    for l in open(p).read().split('\n'):
        if re.match(r'\s*#\[cfg\(test\)\]', l): break
        out.append('' if l.strip().startswith('//') else l)
    return out
lib = [p for p in rs('crates') if '/src/' in p]
src_lines = sum(len(open(p).read().split('\n')) - 1 for p in rs('src'))
kinds = {
    'train': r'\bTrain\b|"train"',
    'walk-past': r'WalkPast|\bwalk_past\b',
    'reversal': r'\bReversal\b|"reversal"',
    'undetermined': r'Undetermined|undetermined',
}
naming_any, naming_all, naming_undet, listing = [], [], [], []
for p in lib:
    text = '\n'.join(code(p))
    hit = [k for k, pat in kinds.items() if re.search(pat, text)]
    if hit: naming_any.append(p)
    # A file that names three or more kinds lists them (a match, a table, a legend): the
    # files a new kind would have to touch. One or two named is a statistic about those.
    if len(hit) >= 3: listing.append(p)
    if len(hit) == len(kinds): naming_all.append(p)
    if 'undetermined' in hit: naming_undet.append(p)
string_results = [(p, i + 1) for p in lib for i, l in enumerate(code(p))
                  if re.search(r'Result<([^<>]|<[^<>]*>)*,\s*String>', l)]
states = r"'(planned|pending|running|done|failed)'"
sql_states = sum(len(re.findall(states, l)) for p in lib for l in code(p))
sql_files = sorted({os.path.relpath(p, root) for p in lib for l in code(p) if re.search(states, l)})
in_src = {k: sorted({os.path.relpath(p, root) for p in rs('src') for l in code(p) if re.search(v, l)})
          for k, v in {'Slurm polling (take_stock, Queue::ask, queue_of)': r'take_stock|Queue::ask|queue_of',
                       'sleeping (thread::sleep)': r'thread::sleep',
                       'status gathering (store.status() outside report::status)': r'\.status\(\)\?',
                       'import (ledger::import, check_row)': r'ledger::import|check_row'}.items()}
print(f'src/ lines: {src_lines}')
print(f'library files naming an outcome kind: {len(naming_any)}; naming all four '
      f'(train, walk-past, reversal, undetermined): {len(naming_all)}; naming undetermined: {len(naming_undet)}')
print(f'library files listing outcome kinds (three or more named): {len(listing)}')
for p in sorted(listing): print('   lists:', os.path.relpath(p, root))
for p in sorted(set(naming_any) - set(listing)):
    text = '\n'.join(code(p))
    print('   names', ', '.join(k for k, pat in kinds.items() if re.search(pat, text)) + ':',
          os.path.relpath(p, root))
print(f'Result<_, String> in library code: {len(string_results)}')
for p, i in string_results: print(f'   {os.path.relpath(p, root)}:{i}')
print(f'SQL state literals in library code: {sql_states} in {len(sql_files)} files')
for k, v in in_src.items(): print(f'src/ {k}: {", ".join(v) if v else "none"}')
