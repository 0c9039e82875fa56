#!/usr/bin/env bash
# Same spec, same bits, on every platform: build rockfrag for glibc
# (x86_64-unknown-linux-gnu) and for musl (x86_64-unknown-linux-musl, whose
# libm differs from glibc's in the last bits of sin, exp, pow, …), run the
# same work with both and compare every output byte for byte:
#   - the default study and studies/museum-object.toml: outcomes.csv,
#     fragility.csv, risk.csv (rockfrag risk over the example hazard curve),
#     and every other file of the two folders (fragility_bootstrap.csv,
#     fragility_curves.csv, fragility.xml, summary.md, the figures'
#     SVGs, manifest.json less its times and thread count);
#   - `rockfrag motion --seed 3 --pga 0.5` (the record CSV);
#   - `rockfrag simulate` on that record file (the glibc build's, for both)
#     and on synthetic records, several blocks and integrators: the JSON
#     outcome and the time history.
# Prints one line per compared file that differs and a verdict; exits 1 on
# any difference (2 when it cannot run).
#
# Usage: scripts/check-platforms.sh [WORKDIR]   (default: a fresh temp dir)
# Needs the musl target (`rustup target add x86_64-unknown-linux-musl`; the
# script adds it when rustup is there). No C toolchain for musl is needed:
# rockfrag has no C code. Set CHECK_PLATFORMS_NO_BUILD=1 to use the binaries
# already built, and CHECK_PLATFORMS_GNU_BIN / CHECK_PLATFORMS_MUSL_BIN to
# compare two other binaries (say, of an older commit).
set -euo pipefail
cd "$(dirname "$0")/.."

musl=x86_64-unknown-linux-musl
work=${1:-$(mktemp -d -t rockfrag-platforms.XXXXXX)}
mkdir -p "$work"
start=$SECONDS

if [ -z "${CHECK_PLATFORMS_NO_BUILD:-}" ]; then
    if ! rustup target list --installed 2>/dev/null | grep -qx "$musl"; then
        echo "adding the $musl target"
        rustup target add "$musl" || { echo "cannot add $musl" >&2; exit 2; }
    fi
    echo "building for glibc and for musl"
    cargo build --release --quiet
    cargo build --release --quiet --target "$musl"
fi
declare -A bin=([gnu]=${CHECK_PLATFORMS_GNU_BIN:-target/release/rockfrag}
    [musl]=${CHECK_PLATFORMS_MUSL_BIN:-target/$musl/release/rockfrag})
for p in gnu musl; do
    [ -x "${bin[$p]}" ] || { echo "missing ${bin[$p]}" >&2; exit 2; }
done
# the two really link different C libraries
if ldd "${bin[musl]}" 2>&1 | grep -q 'libc.so'; then
    echo "${bin[musl]} is not a static musl binary" >&2
    exit 2
fi

hazard=studies/hazard/hazard_curve-mean-PGA_example.csv
run_all() {
    local b=${bin[$1]} out=$work/$1
    rm -rf "$out"
    mkdir -p "$out/simulate"
    "$b" run --out "$out/default" >/dev/null
    "$b" run studies/museum-object.toml --out "$out/museum" >/dev/null
    for s in default museum; do
        "$b" risk "$out/$s" --hazard "$hazard" >/dev/null
        # times and the thread count are the run's, not results
        grep -v -e '"wall_seconds"' -e '"threads"' -e '"started_' -e '"finished_' \
            "$out/$s/manifest.json" >"$out/$s/manifest.cmp"
        rm "$out/$s/manifest.json"
    done
    "$b" motion --seed 3 --pga 0.5 --out "$out/motion.csv" >/dev/null
    # the same record file for both builds: the glibc one's
    local rec=$work/gnu/motion.csv
    local i=0
    for args in "--aspect 4" "--aspect 4 --restitution 0.9" "--aspect 6 --restitution 0.6 --mu-s 0.7 --mu-k 0.6" \
        "--aspect 4 --restitution 0.3 --integrator dopri5" "--aspect 6 --model linear" \
        "--aspect 4 --restitution 0.9 --follow-cascades --audit-energy"; do
        i=$((i + 1))
        # shellcheck disable=SC2086
        "$b" simulate --motion "$rec" $args --json --history "$out/simulate/file-$i.csv" >"$out/simulate/file-$i.json"
        for seed in 1 2 3 4 5; do
            # shellcheck disable=SC2086
            "$b" simulate --seed "$seed" --pga 0.6 $args --json >"$out/simulate/seed$seed-$i.json"
        done
    done
}
# progress and notes go to a log per build (not compared); a failing command
# stops the script (set -e) with status 2
exec 3>&2
state=running
trap '[ "$state" = done ] || { echo "check-platforms: a build or run failed (logs: $work/*.log)" >&3; exit 2; }' EXIT
run_all gnu 2>"$work/gnu.log"
run_all musl 2>"$work/musl.log"

differ=0
compared=0
while IFS= read -r f; do
    compared=$((compared + 1))
    if [ ! -f "$work/musl/$f" ]; then
        echo "DIFFERS $f: missing from the musl build's output"
        differ=$((differ + 1))
    elif ! cmp -s "$work/gnu/$f" "$work/musl/$f"; then
        lines=$(diff "$work/gnu/$f" "$work/musl/$f" | grep -c '^<' || true)
        echo "DIFFERS $f: $lines of $(wc -l <"$work/gnu/$f") lines"
        differ=$((differ + 1))
    fi
done < <(cd "$work/gnu" && find . -type f | sed 's|^\./||' | sort)
for f in default/outcomes.csv default/fragility.csv default/risk.csv museum/outcomes.csv \
    museum/fragility.csv museum/risk.csv motion.csv; do
    [ -s "$work/gnu/$f" ] || { echo "missing $f" >&3; exit 2; }
done

state=done
echo "compared $compared files (glibc vs musl) in $work, $((SECONDS - start)) s"
if [ "$differ" -ne 0 ]; then
    echo "FAIL: $differ of $compared outputs differ between glibc and musl:" \
        "some result depends on the platform's math library (see src/detmath.rs)"
    exit 1
fi
echo "OK: glibc and musl builds give byte-identical outputs"
