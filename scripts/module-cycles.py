#!/usr/bin/env python3
"""Finds import circles between a crate's top-level modules.

Reads every `crate::<module>` path (in `use` lines and inline) in each .rs file under a crate's
src/, maps the file to its top-level module (src/a.rs and src/a/** are `a`; lib.rs is the root
and ignored) and prints each strongly connected component of two or more modules with the
edges that close it. Exit status 1 when there is one. Usage: module-cycles.py CRATE_DIR...
"""
import re
import sys
from pathlib import Path


def top_module(src: Path, f: Path):
    rel = f.relative_to(src).parts
    if rel in (("lib.rs",), ("main.rs",)):
        return None
    return rel[0][:-3] if rel[0].endswith(".rs") else rel[0]


def crate_refs(text: str):
    text = re.sub(r"//[^\n]*", "", text)
    refs = set(re.findall(r"\bcrate::([a-z_][a-z0-9_]*)", text))
    for group in re.findall(r"\bcrate::\{([^}]*(?:\{[^}]*\}[^}]*)*)\}", text, re.S):
        depth = 0
        item = ""
        for ch in group + ",":
            if ch == "{":
                depth += 1
            elif ch == "}":
                depth -= 1
            if ch == "," and depth == 0:
                m = re.match(r"\s*([a-z_][a-z0-9_]*)", item)
                if m:
                    refs.add(m.group(1))
                item = ""
            else:
                item += ch
    return refs


def sccs(graph):
    index, low, stack, on, out, i = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = i[0]
        i[0] += 1
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            out.append(sorted(comp))

    for v in list(graph):
        if v not in index:
            visit(v)
    return out


def main():
    found = False
    for crate in sys.argv[1:]:
        src = Path(crate) / "src"
        modules = {p.stem if p.is_file() else p.name for p in src.iterdir()} - {"lib", "main"}
        graph, why = {}, {}
        for f in sorted(src.rglob("*.rs")):
            m = top_module(src, f)
            if m is None:
                continue
            for r in crate_refs(f.read_text()):
                if r in modules and r != m:
                    graph.setdefault(m, set()).add(r)
                    why.setdefault((m, r), str(f.relative_to(crate)))
        for comp in sccs(graph):
            if len(comp) > 1:
                found = True
                print(f"{crate}: circle among {', '.join(comp)}")
                for a in comp:
                    for b in sorted(graph.get(a, ())):
                        if b in comp:
                            print(f"  {a} -> {b} ({why[(a, b)]})")
    if not found:
        print("no import circle between top-level modules")
    sys.exit(1 if found else 0)


main()
