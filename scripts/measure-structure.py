#!/usr/bin/env python3
# Structure counts of the code (issue 27): functions of 80 lines or more, files over 500 lines
# and expect( in library code, outside tests. Usage: python3 scripts/measure-structure.py crates src
import re,os,sys
def files(roots):
    for r in roots:
        for root,_,fs in os.walk(r):
            if '/tests' in root or 'target' in root: continue
            for f in fs:
                if f.endswith('.rs'): yield os.path.join(root,f)
def strip_tests(lines):
    out=[]
    for i,l in enumerate(lines):
        if re.match(r'\s*#\[cfg\(test\)\]',l): break
        out.append(l)
    return out
long=[];big=[];expects=[]
for p in files(sys.argv[1:]):
    L=strip_tests(open(p).read().split('\n'))
    if len(L)>500: big.append((len(L),p))
    lib = not p.startswith('src/') and not p.startswith('./src/')
    for i,l in enumerate(L):
        if lib and 'expect(' in l and not l.strip().startswith('//'):
            prev=L[i-1].strip() if i else ''
            expects.append((p,i+1,prev.startswith('//') or '//' in l))
        m=re.match(r'(\s*)(pub(\([a-z]+\))? )?(async )?(const )?(unsafe )?(extern "C" )?fn (\w+)',l)
        if m and not l.rstrip().endswith(';'):
            ind=m.group(1)
            for j in range(i+1,len(L)):
                if L[j]==ind+'}' :
                    n=j-i+1
                    if n>=80: long.append((n,p,m.group(8)))
                    break
long.sort(reverse=True)
print('functions >= 80 lines:',len(long))
for x in long: print('  ',x)
print('files > 500 lines:',len(big))
for x in sorted(big,reverse=True): print('  ',x)
print('expect( in library code:',len(expects),' without a comment:',sum(1 for e in expects if not e[2]))
for e in expects:
    if not e[2]: print('  ',e)
