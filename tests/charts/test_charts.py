"""scripts/charts.py on a fixed pair of result tables: the aggregation, the Pareto front and the
SVG's points and labels (python3 -m unittest; run by CTest as charts.unit)."""
import importlib.util
import os
import re
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
spec = importlib.util.spec_from_file_location(
    'charts', os.path.join(HERE, '..', '..', 'scripts', 'charts.py'))
charts = importlib.util.module_from_spec(spec)
spec.loader.exec_module(charts)

TABLES = """# two scenes

### a (64x64, 1 light)

| method | colour correctness | PSNR dB | mean abs | max abs | vs angular: mean / max | frame ms | time / Gouraud |
|---|---|---|---|---|---|---|---|
| gouraud | 0.9500 | 20.0 | 10.000 | 100 | 10.0 / 100 | 0.10 | 1.00 |
| slow-good | 0.9990 | 40.0 | 0.500 | 4 | 0.5 / 4 | 1.00 | 10.00 |
| fast-good | 0.9900 | 30.0 | 2.000 | 30 | 2.0 / 30 | 0.20 | 2.00 |
| dominated | 0.9800 | 25.0 | 4.000 | 60 | 4.0 / 60 | 0.40 | 4.00 |
| fast-good-noskip | 0.9900 | 30.0 | 2.000 | 30 | 2.0 / 30 | 0.30 | 3.00 |
| llvmpipe | 1.0000 | 70.0 | 0.001 | 1 | 0.0 / 1 | 0.50 | 5.00 |

### b (64x64, 1 light)

| method | colour correctness | PSNR dB | mean abs | max abs | vs angular: mean / max | frame ms | time / Gouraud |
|---|---|---|---|---|---|---|---|
| gouraud | 0.9700 | 20.0 | 10.000 | 80 | 10.0 / 80 | 0.10 | 1.00 |
| slow-good | 0.9990 | 40.0 | 0.500 | 6 | 0.5 / 6 | 1.00 | 40.00 |
| fast-good | 0.9800 | 30.0 | 2.000 | 20 | 2.0 / 20 | 0.20 | 2.00 |
| dominated | 0.9700 | 25.0 | 4.000 | 50 | 4.0 / 50 | 0.40 | 4.00 |
| fast-good-noskip | 0.9800 | 30.0 | 2.000 | 20 | 2.0 / 20 | 0.30 | 3.00 |
| llvmpipe | 1.0000 | 70.0 | 0.001 | 1 | 0.0 / 1 | 0.50 | 5.00 |
"""


class Charts(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp()
        self.tables = os.path.join(self.dir, 'tables.md')
        with open(self.tables, 'w', encoding='utf-8') as f:
            f.write(TABLES)

    def points(self, drop_noskip=True):
        order, rows = charts.read_tables(self.tables)
        return {p['method']: p for p in charts.aggregate(order, rows, drop_noskip)}

    def test_aggregates_each_method_over_the_scenes(self):
        p = self.points()
        self.assertEqual(set(p), {'gouraud', 'slow-good', 'fast-good', 'dominated', 'llvmpipe'})
        self.assertAlmostEqual(p['slow-good']['time'], 20.0)  # geometric mean of 10 and 40
        self.assertAlmostEqual(p['fast-good']['correctness'], 0.985)
        self.assertEqual(p['dominated']['max_error'], 60)  # the worst scene's
        self.assertIn('fast-good-noskip', self.points(drop_noskip=False))

    def test_the_pareto_front_leaves_out_dominated_methods(self):
        pts = [p for m, p in self.points().items() if m != charts.PEER]
        better = lambda q, p, strict=False: (q['correctness'] > p['correctness'] if strict
                                             else q['correctness'] >= p['correctness'])
        front = [p['method'] for p in charts.pareto(pts, better)]
        self.assertEqual(front, ['gouraud', 'fast-good', 'slow-good'])

    def test_the_svg_has_one_labelled_point_per_method(self):
        prefix = os.path.join(self.dir, 'out')
        for key, higher in (('correctness', True), ('max_error', False)):
            pts = list(self.points().values())
            svg = charts.svg_chart(pts, key, 'title', 'y', higher)
            self.assertEqual(len(re.findall(r'<circle ', svg)), 4)  # the peer is a square
            self.assertEqual(len(re.findall(r'<rect x="[^"]*" y="[^"]*" width="8"', svg)), 1)
            for m in ('gouraud', 'slow-good', 'fast-good', 'dominated', 'llvmpipe'):
                self.assertIn(f'>{m}</text>', svg)
            self.assertEqual(svg.count('<polyline '), 1)
        script = os.path.join(HERE, '..', '..', 'scripts', 'charts.py')
        done = subprocess.run([sys.executable, script, self.tables, '--drop-noskip', '--title', 't',
                               '--out-prefix', prefix], capture_output=True, text=True)
        self.assertEqual(done.returncode, 0, done.stderr)
        for suffix in ('correctness', 'max-error'):
            with open(f'{prefix}-{suffix}.svg', encoding='utf-8') as f:
                self.assertTrue(f.read().startswith('<svg '))

    def test_a_file_without_tables_is_refused(self):
        empty = os.path.join(self.dir, 'empty.md')
        with open(empty, 'w', encoding='utf-8') as f:
            f.write('# nothing here\n')
        script = os.path.join(HERE, '..', '..', 'scripts', 'charts.py')
        done = subprocess.run([sys.executable, script, empty, '--title', 't', '--out-prefix',
                               os.path.join(self.dir, 'x')], capture_output=True, text=True)
        self.assertNotEqual(done.returncode, 0)
        self.assertIn('no method table with Gouraud', done.stderr)


if __name__ == '__main__':
    unittest.main()
