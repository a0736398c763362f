#!/usr/bin/env bash
# Re-measure every benchmark, one after the other (never concurrently: the
# machine has 2 cores), and collect the figures in benchmarks/README.md.
set -euo pipefail
cd "$(dirname "$0")/.."
python benchmarks/bench_jets.py
python benchmarks/bench_hopf.py --repeat 21
python benchmarks/bench_simulate.py
python benchmarks/bench_accuracy.py
python benchmarks/bench_ceiling.py
python benchmarks/bench_jets_n.py > benchmarks/results_jets_n.md
python benchmarks/bench_simulate_n.py > benchmarks/results_simulate_n.md
python benchmarks/stress.py
python benchmarks/bench_continue.py > benchmarks/results_continue.md
python benchmarks/bench_curve.py > benchmarks/results_curve.md
python benchmarks/bench_regen_high.py --reps 3 > benchmarks/results_regen_high.md
python benchmarks/bench_l2.py --repeat 21 --verify > benchmarks/results_l2.md
python benchmarks/bench_plane.py > benchmarks/results_plane.md
