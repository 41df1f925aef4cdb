#!/usr/bin/env python3
"""The house drawn from includes: src/'s #include "..." graph, by layer.

The layer order is read from docs/ARCHITECTURE.md ("Layers (arrows point down
only)": its src/<layer>/ lines, top first). A module is a file without its
extension (bake/bake_fit.c and bake/bake_fit.h are one module); a public header
include/nbrdf/<name>.h is a module of the layer PUBLIC names. Fails (exit 1),
listing each, on
  - an upward arrow: a module including one of a higher layer;
  - a cycle inside a layer: modules that include each other, directly or not,
    other than those of KNOWN_CYCLES (older ones, listed so that no new one
    joins them; one that is gone must leave the list too).

  scripts/check_includes.py [ROOT]           check; prints a summary by layer
  scripts/check_includes.py [ROOT] --dot     the graph for Graphviz, layers as clusters
"""
import os
import re
import sys

# The layer each public header belongs to (the lowest one that implements it).
PUBLIC = {
    "status.h": "core", "nbrdf.h": "core", "brdf.h": "brdf", "model.h": "model",
    "gpu_pack.h": "model", "bake.h": "bake", "fit.h": "bake", "verify.h": "verify", "render.h": "render",
}
# Cycles tolerated inside a layer (none now: a format or helper needing its owner's types
# gets them from a header below both; docs/ARCHITECTURE.md, "Layers").
KNOWN_CYCLES = set()
SOURCE = (".c", ".h", ".cpp", ".hpp")
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def layers_from_doc(root):
    text = open(os.path.join(root, "docs", "ARCHITECTURE.md"), encoding="utf-8").read()
    section = text.split("## Layers", 1)[1].split("\n## ", 1)[0]
    order = re.findall(r"^src/([a-z0-9_]+)/", section, re.M)
    if not order:
        sys.exit("check_includes: no src/<layer>/ lines under 'Layers' in docs/ARCHITECTURE.md")
    return order


def module_of(path):
    """(layer, module) of a repository-relative path, or None outside src/ and the public headers."""
    parts = path.split("/")
    stem = os.path.splitext(path)[0]
    if parts[0] == "src" and len(parts) >= 3:
        return parts[1], stem[len("src/"):]
    if parts[:2] == ["include", "nbrdf"] and len(parts) == 3:
        if parts[2] not in PUBLIC:
            sys.exit(f"check_includes: {path}: public header without a layer (add it to PUBLIC)")
        return PUBLIC[parts[2]], "nbrdf/" + os.path.splitext(parts[2])[0]
    return None


def resolve(root, src_path, name):
    """The repository-relative file an #include "name" in src_path reads, or None (generated)."""
    for base in (os.path.dirname(src_path), "src", "include"):
        cand = os.path.normpath(os.path.join(base, name))
        if os.path.isfile(os.path.join(root, cand)):
            return cand
    return None


def graph(root):
    files = []
    for top in ("src", os.path.join("include", "nbrdf")):
        for d, _, names in os.walk(os.path.join(root, top)):
            files += [os.path.relpath(os.path.join(d, n), root) for n in names if n.endswith(SOURCE)]
    layer, edges = {}, {}
    for f in sorted(files):
        m = module_of(f)
        if not m:
            continue
        layer[m[1]] = m[0]
        out = edges.setdefault(m[1], {})
        text = open(os.path.join(root, f), encoding="utf-8", errors="replace").read()
        for name in INCLUDE.findall(text):
            target = resolve(root, f, name)
            t = module_of(target) if target else None
            if t and t[1] != m[1]:
                layer[t[1]] = t[0]
                out.setdefault(t[1], f)
    return layer, edges


def cycles(nodes, edges):
    """Strongly connected components of more than one module (Tarjan, iterative)."""
    index, low, on, stack, out, counter = {}, {}, set(), [], [], [0]
    for start in nodes:
        if start in index:
            continue
        work = [(start, iter(sorted(edges.get(start, ()))))]
        index[start] = low[start] = counter[0]
        counter[0] += 1
        stack.append(start), on.add(start)
        while work:
            v, it = work[-1]
            w = next((w for w in it if w in nodes), None)
            if w is not None:
                if w not in index:
                    index[w] = low[w] = counter[0]
                    counter[0] += 1
                    stack.append(w), on.add(w)
                    work.append((w, iter(sorted(edges.get(w, ())))))
                elif w in on:
                    low[v] = min(low[v], index[w])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[v])
            if low[v] == index[v]:
                comp = []
                while True:
                    w = stack.pop()
                    on.discard(w)
                    comp.append(w)
                    if w == v:
                        break
                if len(comp) > 1:
                    out.append(sorted(comp))
    return out


def main(argv):
    args = [a for a in argv[1:] if not a.startswith("--")]
    root = os.path.abspath(args[0] if args else os.path.join(os.path.dirname(__file__), ".."))
    order = layers_from_doc(root)
    rank = {name: i for i, name in enumerate(order)}  # 0: the top layer
    layer, edges = graph(root)
    unknown = sorted({l for l in layer.values() if l not in rank})
    if unknown:
        sys.exit(f"check_includes: src/ layers missing from docs/ARCHITECTURE.md: {', '.join(unknown)}")
    if "--dot" in argv:
        print("digraph includes {\n  rankdir=TB; node [shape=box, fontsize=9];")
        for name in order:
            mods = sorted(m for m in layer if layer[m] == name)
            print(f'  subgraph "cluster_{name}" {{ label="{name}"; ' +
                  " ".join(f'"{m}";' for m in mods) + " }")
        for m in sorted(edges):
            for t in sorted(edges[m]):
                print(f'  "{m}" -> "{t}";')
        print("}")
        return 0
    problems = []
    for m in sorted(edges):
        for t, via in sorted(edges[m].items()):
            if rank[layer[t]] < rank[layer[m]]:
                problems.append(f"upward: {via} includes {t} ({layer[m]} -> {layer[t]})")
    known = []
    for name in order:
        mods = {m for m in layer if layer[m] == name}
        inner = {m: {t for t in edges.get(m, {}) if t in mods} for m in mods}
        for comp in cycles(sorted(mods), inner):
            if tuple(comp) in KNOWN_CYCLES:
                known.append(tuple(comp))
            else:
                problems.append(f"cycle in {name}: " + ", ".join(comp))
    for gone in sorted(KNOWN_CYCLES - set(known)):
        problems.append("no longer a cycle, remove it from KNOWN_CYCLES: " + ", ".join(gone))
    arrows = sum(len(e) for e in edges.values())
    for name in order:
        mods = [m for m in edges if layer[m] == name]
        down = {}
        for m in mods:
            for t in edges[m]:
                down[layer[t]] = down.get(layer[t], 0) + 1
        print(f"{name:8s} {len(mods):3d} modules -> " +
              ", ".join(f"{l} {down[l]}" for l in order if l in down))
    print(f"{len(edges)} modules, {arrows} arrows, {len(known)} known cycle(s), "
          f"{len(problems)} problem(s)")
    for p in problems:
        print(p)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
