#!/usr/bin/env python3
# Circles between modules inside a crate (a module using one that uses it), from `crate::` and
# `super::` paths outside comments and tests. Usage: python3 scripts/module-cycles.py crates/* .
import re,os,sys,itertools
def mods(crate):
    src=os.path.join(crate,'src'); out={}
    for root,_,fs in os.walk(src):
        for f in fs:
            if not f.endswith('.rs'): continue
            p=os.path.join(root,f); rel=os.path.relpath(p,src)[:-3]
            parts=rel.split(os.sep)
            if parts[-1]=='mod': parts=parts[:-1]
            name='::'.join(parts) if parts!=['lib'] and parts!=['main'] else 'lib'
            txt=open(p).read()
            txt=re.sub(r'//[^\n]*','',txt)
            txt=re.sub(r'(?s)#\[cfg\(test\)\]\s*mod tests\s*\{.*','',txt)
            out[name]=txt
    return out
def edges(ms):
    E={m:set() for m in ms}
    for m,t in ms.items():
        refs=set(re.findall(r'crate::([a-z_][a-z0-9_]*(?:::[a-z_][a-z0-9_]*)*)',t))
        # super:: refs
        base=m.split('::')[:-1]
        for s in re.findall(r'\bsuper::([a-z_][a-z0-9_]*)',t):
            refs.add('::'.join(base+[s]) if base else s)
        for r in refs:
            parts=r.split('::')
            for k in range(len(parts),0,-1):
                c='::'.join(parts[:k])
                if c in ms and c!=m and not m.startswith(c+'::') and c!='lib':
                    E[m].add(c); break
    return E
def cycles(E):
    found=set()
    for a in E:
        for b in E[a]:
            if a in E.get(b,()): found.add(tuple(sorted((a,b))))
    # longer cycles via DFS
    def dfs(start,node,path):
        for n in E[node]:
            if n==start and len(path)>2: found.add(tuple(path))
            elif n not in path and len(path)<5 and n>start: dfs(start,n,path+[n])
    for s in E: dfs(s,s,[s])
    return found
for c in sys.argv[1:]:
    for cy in sorted(cycles(edges(mods(c)))): print(c, ' -> '.join(cy))
