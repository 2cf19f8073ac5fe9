#!/usr/bin/env python3
"""Run time against error as a picture: SVG charts from tinyphong-results' Markdown tables.

    python3 scripts/charts.py --title "One light" --out-prefix docs/charts/one-light TABLES.md

reads every scene table of TABLES.md (the output of build/release/bench/tinyphong-results),
aggregates each method over the scenes (geometric mean of the time ratio to Gouraud, mean colour
correctness, the largest max |error|) and writes two charts:

    PREFIX-correctness.svg   time / Gouraud (log scale) against colour correctness (Vlasic eq. 6.1)
    PREFIX-max-error.svg     time / Gouraud (log scale) against max |error| in levels

every method a labelled point, the Pareto front (no other method both faster and better) drawn
as a line, the peer (llvmpipe) as a hollow square. Verification variants (-noskip: the same image
as their method, slower) are left out with --drop-noskip. Plain SVG, no plotting package.
"""
import argparse
import math
import sys
from xml.sax.saxutils import escape

PEER = 'llvmpipe'


def read_tables(path):
    """{method: [(correctness, max_abs, time_ratio), ...]} over every scene table in path."""
    rows = {}
    order = []
    header = None
    for line in open(path, encoding='utf-8'):
        cells = [c.strip() for c in line.strip().strip('|').split('|')]
        if not line.startswith('|') or len(cells) < 2:
            header = None if not line.startswith('|') else header
            continue
        if cells[0] == 'method':
            header = cells
            continue
        if header is None or set(cells[0]) <= set('-: '):
            continue
        col = {name: i for i, name in enumerate(header)}
        try:
            cc = float(cells[col['colour correctness']])
            mx = float(cells[col['max abs']])
            t = float(cells[col['time / Gouraud']])
        except (KeyError, ValueError, IndexError):
            continue
        if cells[0] not in rows:
            order.append(cells[0])
            rows[cells[0]] = []
        rows[cells[0]].append((cc, mx, t))
    return order, rows


def aggregate(order, rows, drop_noskip):
    out = []
    for m in order:
        if drop_noskip and m.endswith('-noskip'):
            continue
        v = rows[m]
        time = math.exp(sum(math.log(max(t, 1e-6)) for _, _, t in v) / len(v))
        out.append({'method': m, 'time': time, 'correctness': sum(c for c, _, _ in v) / len(v),
                    'max_error': max(x for _, x, _ in v), 'scenes': len(v)})
    return out


def pareto(points, better):
    """The points no other point beats: faster (or as fast) and better (or as good)."""
    front = []
    for p in points:
        dominated = any(q is not p and q['time'] <= p['time'] and better(q, p) and
                        (q['time'] < p['time'] or better(q, p, strict=True)) for q in points)
        if not dominated:
            front.append(p)
    return sorted(front, key=lambda p: p['time'])


def nice_below(v):
    """The largest of 1, 2, 5 times a power of ten at most v."""
    e = 10 ** math.floor(math.log10(v))
    return max(k * e for k in (1, 2, 5) if k * e <= v)


def nice_above(v):
    e = 10 ** math.floor(math.log10(v))
    return min(k * e for k in (1, 2, 5, 10) if k * e >= v)


def svg_chart(points, key, title, ylabel, higher_is_better, width=760, height=480):
    left, right, top, bottom = 70, 170, 40, 56
    pw, ph = width - left - right, height - top - bottom
    xs = [p['time'] for p in points]
    lo, hi = nice_below(min(xs) / 1.15), nice_above(max(xs) * 1.15)
    ys = [p[key] for p in points]
    step = nice_above((max(ys) - min(ys)) / 5 or 0.01)
    ymin = math.floor(min(ys) / step) * step
    ymax = math.ceil(max(ys) / step) * step
    if ymax - max(ys) < step / 4:  # room above the top point for its label
        ymax += step / 2
    if key != 'correctness':
        ymin = max(ymin, 0.0)
    def X(t):
        return left + pw * (math.log10(t) - math.log10(lo)) / (math.log10(hi) - math.log10(lo))

    def Y(v):
        return top + ph * (ymax - v) / (ymax - ymin)

    def better(q, p, strict=False):
        if higher_is_better:
            return q[key] > p[key] if strict else q[key] >= p[key]
        return q[key] < p[key] if strict else q[key] <= p[key]

    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" '
           f'viewBox="0 0 {width} {height}" font-family="sans-serif" font-size="11">',
           f'<rect width="{width}" height="{height}" fill="white"/>',
           f'<text x="{left}" y="22" font-size="14" font-weight="bold">{escape(title)}</text>']
    # Axes and grid: decades and their 2x, 5x on x; five steps on y.
    decade = 10 ** math.floor(math.log10(lo))
    while decade <= hi * 1.0001:
        for k in (1, 2, 5):
            t = decade * k
            if t < lo * 0.999 or t > hi * 1.001:
                continue
            x = X(t)
            out.append(f'<line x1="{x:.1f}" y1="{top}" x2="{x:.1f}" y2="{top + ph}" '
                       f'stroke="{"#bbb" if k == 1 else "#e4e4e4"}"/>')
            out.append(f'<text x="{x:.1f}" y="{top + ph + 16}" text-anchor="middle">{t:g}</text>')
        decade *= 10
    digits = max(0, -math.floor(math.log10(step)))
    v = ymin
    while v <= ymax + step * 1e-6:
        y = Y(v)
        out.append(f'<line x1="{left}" y1="{y:.1f}" x2="{left + pw}" y2="{y:.1f}" stroke="#e4e4e4"/>')
        out.append(f'<text x="{left - 6}" y="{y + 4:.1f}" text-anchor="end">{v:.{digits}f}</text>')
        v += step
    out.append(f'<rect x="{left}" y="{top}" width="{pw}" height="{ph}" fill="none" stroke="#333"/>')
    out.append(f'<text x="{left + pw / 2:.1f}" y="{height - 14}" text-anchor="middle">'
               'time / Gouraud (log scale; geometric mean over the scenes)</text>')
    out.append(f'<text transform="translate(16 {top + ph / 2:.1f}) rotate(-90)" '
               f'text-anchor="middle">{escape(ylabel)}</text>')
    front = pareto([p for p in points if p['method'] != PEER], better)
    if len(front) > 1:
        path = ' '.join(f'{X(p["time"]):.1f},{Y(p[key]):.1f}' for p in front)
        out.append(f'<polyline points="{path}" fill="none" stroke="#2a7" stroke-width="2" '
                   'stroke-dasharray="5 3"/>')
    on_front = {p['method'] for p in front}
    # The legend in the right margin's foot; each label at the first place round its point that
    # overlaps no point, no label placed and not the legend.
    lx0, ly0 = left + pw + 10, top + ph - 40
    legend = (('#2a7', '● on the Pareto front'), ('#36c', '● dominated'), ('#c40', f'□ peer ({PEER})'))
    for i, (colour, text) in enumerate(legend):
        out.append(f'<text x="{lx0}" y="{ly0 + 16 * i}" fill="{colour}">{escape(text)}</text>')
    marks = [(X(p['time']), Y(p[key])) for p in points]
    boxes = [(lx0, ly0 - 12, right - 12, 48)]
    for p in sorted(points, key=lambda p: (Y(p[key]), X(p['time']))):
        x, y = X(p['time']), Y(p[key])
        w, h = 6.3 * len(p['method']), 11
        candidates = [(x + 7, y + 4), (x - 7 - w, y + 4), (x - w / 2, y - 8), (x - w / 2, y + 16)]
        candidates += [(x + 7, y + 4 + d) for k in range(1, 8) for d in (12 * k, -12 * k)]
        def free(c):
            bx, by = c[0], c[1] - h + 2
            if bx < left + 2 or bx + w > left + pw + right - 4 or by < top or by + h > top + ph:
                return False
            if any(bx - 5 < mx < bx + w + 5 and by - 5 < my < by + h + 5 for mx, my in marks):
                return False
            return not any(bx < ox + ow and ox < bx + w and by < oy + oh and oy < by + h
                           for ox, oy, ow, oh in boxes)
        lx, ly = next((c for c in candidates if free(c)), candidates[0])
        boxes.append((lx, ly - h + 2, w, h))
        if p['method'] == PEER:
            out.append(f'<rect x="{x - 4:.1f}" y="{y - 4:.1f}" width="8" height="8" fill="white" '
                       'stroke="#c40" stroke-width="2"/>')
        else:
            colour = '#2a7' if p['method'] in on_front else '#36c'
            out.append(f'<circle cx="{x:.1f}" cy="{y:.1f}" r="4" fill="{colour}"/>')
        if math.hypot(lx - x, ly - 4 - y) > 20:  # a label moved away: a leader to its point
            ax = lx if lx > x else lx + w
            out.append(f'<line x1="{x:.1f}" y1="{y:.1f}" x2="{ax:.1f}" y2="{ly - 4:.1f}" '
                       'stroke="#aaa"/>')
        out.append(f'<text x="{lx:.1f}" y="{ly:.1f}">{escape(p["method"])}</text>')
    out.append('</svg>')
    return '\n'.join(out) + '\n'


def main():
    ap = argparse.ArgumentParser(description=' '.join(__doc__.split('\n\n')[0].split()))
    ap.add_argument('tables', help="tinyphong-results' Markdown output")
    ap.add_argument('--title', required=True)
    ap.add_argument('--out-prefix', required=True)
    ap.add_argument('--drop-noskip', action='store_true')
    a = ap.parse_args()
    try:
        order, rows = read_tables(a.tables)
    except OSError as e:
        sys.exit(f'charts.py: {a.tables}: {e.strerror}')
    points = aggregate(order, rows, a.drop_noskip)
    if len(points) < 2 or not any(p['method'] == 'gouraud' for p in points):
        sys.exit(f'{a.tables}: no method table with Gouraud found')
    for key, suffix, ylabel, higher in (
            ('correctness', 'correctness', 'colour correctness (mean over the scenes)', True),
            ('max_error', 'max-error', 'max |error| in levels (worst scene)', False)):
        out = f'{a.out_prefix}-{suffix}.svg'
        try:
            with open(out, 'w', encoding='utf-8') as f:
                f.write(svg_chart(points, key, f'{a.title}: {ylabel} against run time', ylabel, higher))
        except OSError as e:
            sys.exit(f'charts.py: {out}: {e.strerror}')
        print(f'wrote {a.out_prefix}-{suffix}.svg ({len(points)} methods)')


if __name__ == '__main__':
    main()
