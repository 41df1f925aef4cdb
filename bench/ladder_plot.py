#!/usr/bin/env python3
"""The accuracy ladder's trade as a plot: bake CPU time against `nbrdf verify`'s median
lobe error, one point per (scene, level) row of bench/ladder_trade.sh's markdown tables.
Writes SVG (no plotting library needed; any browser shows it).

    python3 bench/ladder_plot.py OUT.svg TABLE.md [TABLE.md ...]

Constants are small points, the maps (rows whose scene is not `layer#N`) large ones;
sharp low-IOR coats are outlined; the x axis is logarithmic."""
import math
import sys

COLOURS = {"fast": "#888888", "fitted": "#1f77b4", "specialised": "#d62728",
           "compact": "#2ca02c"}


def rows(paths):
    for path in paths:
        for line in open(path, encoding="utf-8"):
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            if len(cells) < 7 or not cells[2].endswith(" s") or cells[1] not in COLOURS:
                continue
            yield {"scene": cells[0], "level": cells[1],
                   "cpu": max(float(cells[3].rstrip(" s")), 0.5),
                   "median": float(cells[4].rstrip(" %"))}


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    pts = list(rows(sys.argv[2:]))
    if not pts:
        sys.exit("ladder_plot: no table rows in " + " ".join(sys.argv[2:]))
    W, H, L, B, T, R = 640, 420, 60, 50, 20, 150
    x0, x1 = math.log10(0.5), math.log10(max(p["cpu"] for p in pts) * 1.5)
    y1 = max(5.0, math.ceil(max(p["median"] for p in pts) / 5.0) * 5.0)

    def X(v):
        return L + (math.log10(v) - x0) / (x1 - x0) * (W - L - R)

    def Y(v):
        return H - B - v / y1 * (H - B - T)

    out = ['<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" '
           'font-family="sans-serif" font-size="12">' % (W, H),
           '<rect width="100%" height="100%" fill="white"/>']
    for e in range(math.floor(x0), math.ceil(x1) + 1):
        for m in (1, 2, 5):
            v = m * 10 ** e
            if x0 <= math.log10(v) <= x1:
                out.append('<line x1="%.1f" y1="%d" x2="%.1f" y2="%d" stroke="#eee"/>'
                           % (X(v), T, X(v), H - B))
                out.append('<text x="%.1f" y="%d" text-anchor="middle">%g</text>'
                           % (X(v), H - B + 16, v))
    for v in range(0, int(y1) + 1, 5):
        out.append('<line x1="%d" y1="%.1f" x2="%d" y2="%.1f" stroke="#eee"/>'
                   % (L, Y(v), W - R, Y(v)))
        out.append('<text x="%d" y="%.1f" text-anchor="end">%d %%</text>' % (L - 6, Y(v) + 4, v))
    out.append('<text x="%d" y="%d" text-anchor="middle">bake CPU seconds (log)</text>'
               % ((L + W - R) // 2, H - 12))
    out.append('<text x="16" y="%d" transform="rotate(-90 16 %d)" text-anchor="middle">'
               'verify median lobe error</text>' % ((T + H - B) // 2, (T + H - B) // 2))
    for p in pts:
        maps = not p["scene"].startswith("layer#")
        sharp = "sharp" in p["scene"]
        out.append('<circle cx="%.1f" cy="%.1f" r="%d" fill="%s" fill-opacity="0.7"%s>'
                   '<title>%s %s: %.0f s, %.1f %%</title></circle>'
                   % (X(p["cpu"]), Y(p["median"]), 7 if maps else 3, COLOURS[p["level"]],
                      ' stroke="black" stroke-width="1.5"' if sharp else "",
                      p["scene"], p["level"], p["cpu"], p["median"]))
    y = T + 10
    for level, colour in COLOURS.items():
        if any(p["level"] == level for p in pts):
            out.append('<circle cx="%d" cy="%d" r="5" fill="%s"/><text x="%d" y="%d">%s</text>'
                       % (W - R + 20, y, colour, W - R + 32, y + 4, level))
            y += 20
    out.append('<circle cx="%d" cy="%d" r="7" fill="none" stroke="#444"/><text x="%d" y="%d">'
               'maps</text>' % (W - R + 20, y, W - R + 32, y + 4))
    out.append('<circle cx="%d" cy="%d" r="3" fill="none" stroke="black" stroke-width="1.5"/>'
               '<text x="%d" y="%d">sharp coat</text>' % (W - R + 20, y + 20, W - R + 32, y + 24))
    out.append("</svg>")
    with open(sys.argv[1], "w", encoding="utf-8") as f:
        f.write("\n".join(out) + "\n")


if __name__ == "__main__":
    main()
