#!/usr/bin/env bash
# Where the instructions of a study go, per analysis: callgrind (valgrind)
# counts every instruction of `rockfrag run` on one thread, and
# scripts/profile_table.py sorts them into the stages of a run (synthesis,
# scaling, the Taylor steps, event searches, bounds, impacts, bookkeeping,
# CSV rows, reading back, fit and bootstrap, figures) as a Markdown table.
# Instruction counts do not depend on the machine's load, unlike times.
#
# Usage: scripts/profile.sh [STUDY.toml] [RECORDS]
#   STUDY    default studies/fragility-100k.toml
#   RECORDS  records per stripe of the profiled copy of the study (default
#            25; 0 keeps the study's own). Synthesis, solving and the CSV
#            rows scale with the analyses; the fit, its bootstrap and the
#            figures mostly do not (per case and stripe), so their share
#            per analysis is larger in a reduced copy than in the study.
# Needs valgrind (Debian: apt-get install valgrind). Writes the table to
# standard output and keeps callgrind's file in a temp dir (named on
# standard error). Takes about 60 times the run's CPU time.
set -euo pipefail
cd "$(dirname "$0")/.."
study=${1:-studies/fragility-100k.toml}
records=${2:-25}
command -v valgrind >/dev/null || { echo "profile.sh: needs valgrind" >&2; exit 2; }
cargo build --release --quiet
work=$(mktemp -d -t rockfrag-profile.XXXXXX)
spec=$work/$(basename "$study")
if [ "$records" != 0 ]; then
    sed -E "s/^records = [0-9]+/records = $records/" "$study" >"$spec"
else
    cp "$study" "$spec"
fi
echo "profiling $study (records = $records) in $work" >&2
valgrind --tool=callgrind --callgrind-out-file="$work/callgrind.out" \
    target/release/rockfrag run "$spec" --out "$work/out" --threads 1 --force >"$work/run.log" 2>&1
analyses=$(($(wc -l <"$work/out/outcomes.csv") - 1))
python3 scripts/profile_table.py "$work/callgrind.out" "$analyses"
