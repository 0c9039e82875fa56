#!/usr/bin/env bash
# Checks that OpenQuake 3.26.2 and pelicun 3.10.0 compute rockfrag's numbers from what rockfrag
# exports for them.
#
#   scripts/check-clients.sh STUDY [--openquake JOBDIR] [--pelicun FOLDER]
#                                  [--hazard FILE [--site K]] [--emulate] [--keep]
#
# STUDY     a rockfrag results folder (fragility.csv, fragility.xml; risk.csv for OpenQuake)
# --openquake JOBDIR   an OpenQuake classical_damage job folder (job.ini, exposure.xml,
#           fragility.xml, hazard.csv). Run with the engine; annual rates compared with
#           STUDY/risk.csv within 1 %. With --hazard and no JOBDIR (or a JOBDIR that does not
#           exist) the job is first written by `rockfrag export openquake`.
# --pelicun FOLDER     a pelicun damage DB folder (<name>.csv + <name>.json). Loaded unmodified;
#           P(DS >= k) at fixed PGAs compared with Phi(ln(IM/theta)/beta) within 2e-3 (LHS,
#           N = 1000). Written first by `rockfrag export pelicun` when FOLDER is missing.
# --hazard FILE [--site K]   the OpenQuake hazard-curve CSV the job is (to be) written from:
#           `rockfrag risk STUDY --hazard FILE --site K` is rerun so that risk.csv matches it.
# --emulate  evaluate the job with OpenQuake's own functions instead of `oq engine --run`.
# --keep     keep the folders written into a temporary directory (printed).
# With neither --openquake nor --pelicun both are checked (the job needs --hazard).
#
# Environment: ROCKFRAG (default target/release/rockfrag of this repository), OQ_VENV and
# PELICUN_VENV (the venvs made by ../shared/tools/{openquake/engine_env.sh,pelicun/pelicun_env.sh}).
# Prints each tool's table and a final line `check-clients: PASS|FAIL ...`; exit 0 on PASS.
set -uo pipefail
HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
REPO=$(cd "$HERE/.." && pwd)
TOOLS=${ROCKFRAG_TOOLS:-$(cd "$REPO/.." && pwd)/shared/tools}
ROCKFRAG=${ROCKFRAG:-$REPO/target/release/rockfrag}

usage() { sed -n '2,28p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; exit 2; }
[ $# -ge 1 ] || usage
STUDY=""; JOB=""; PEL=""; HAZ=""; SITE=0; EMULATE=""; KEEP=""; DO_OQ=""; DO_PEL=""
while [ $# -gt 0 ]; do
  case "$1" in
    --openquake) DO_OQ=1; if [ $# -ge 2 ] && [ "${2#--}" = "$2" ]; then JOB=$2; shift; fi ;;
    --pelicun) DO_PEL=1; if [ $# -ge 2 ] && [ "${2#--}" = "$2" ]; then PEL=$2; shift; fi ;;
    --hazard) HAZ=$2; shift ;;
    --site) SITE=$2; shift ;;
    --emulate) EMULATE=--emulate ;;
    --keep) KEEP=1 ;;
    -h|--help) usage ;;
    -*) echo "unknown option $1" >&2; usage ;;
    *) [ -z "$STUDY" ] || usage; STUDY=$1 ;;
  esac
  shift
done
[ -n "$STUDY" ] || usage
[ -f "$STUDY/fragility.csv" ] || { echo "$STUDY: no fragility.csv (run rockfrag run/fragility first)" >&2; exit 2; }
if [ -z "$DO_OQ$DO_PEL" ]; then DO_OQ=1; DO_PEL=1; fi

TMP=$(mktemp -d /tmp/check-clients.XXXXXX)
cleanup() { if [ -n "$KEEP" ]; then echo "kept $TMP" >&2; else rm -rf "$TMP"; fi; }
trap cleanup EXIT

RESULT_OQ=skipped; RESULT_PEL=skipped; STATUS=0

if [ -n "$DO_OQ" ]; then
  if [ -z "$JOB" ] || [ ! -f "$JOB/job.ini" ]; then
    [ -n "$HAZ" ] || { echo "OpenQuake: no job folder and no --hazard to write one from" >&2; exit 2; }
    JOB=${JOB:-$TMP/openquake}
    "$ROCKFRAG" export openquake "$STUDY" --hazard "$HAZ" --site "$SITE" --out "$JOB" || exit 2
  fi
  if [ -n "$HAZ" ]; then
    "$ROCKFRAG" risk "$STUDY" --hazard "$HAZ" --site "$SITE" >/dev/null || { echo "rockfrag risk failed" >&2; exit 2; }
  fi
  [ -f "$STUDY/risk.csv" ] || { echo "$STUDY: no risk.csv: give --hazard FILE --site K" >&2; exit 2; }
  OQ=$(OQ_VENV=${OQ_VENV:-} "$TOOLS/openquake/engine_env.sh") || { echo "no OpenQuake venv" >&2; exit 2; }
  echo "== OpenQuake $("$OQ/bin/python" -c 'import openquake.engine as e; print(e.__version__)' 2>/dev/null): $JOB"
  if "$OQ/bin/python" "$HERE/check_openquake.py" "$STUDY" "$JOB" $EMULATE; then RESULT_OQ=PASS; else RESULT_OQ=FAIL; STATUS=1; fi
fi

if [ -n "$DO_PEL" ]; then
  if [ -z "$PEL" ] || ! ls "$PEL"/*.csv >/dev/null 2>&1; then
    PEL=${PEL:-$TMP/pelicun}
    "$ROCKFRAG" export pelicun "$STUDY" --out "$PEL" || exit 2
  fi
  PV=$(PELICUN_VENV=${PELICUN_VENV:-} "$TOOLS/pelicun/pelicun_env.sh") || { echo "no pelicun venv" >&2; exit 2; }
  echo "== pelicun $("$PV/bin/python" -c 'import pelicun; print(pelicun.__version__)' 2>/dev/null): $PEL"
  if "$PV/bin/python" "$HERE/check_pelicun.py" "$STUDY" "$PEL" --quiet; then RESULT_PEL=PASS; else RESULT_PEL=FAIL; STATUS=1; fi
fi

if [ $STATUS -eq 0 ]; then V=PASS; else V=FAIL; fi
echo "check-clients: $V ($(basename "$STUDY"): openquake $RESULT_OQ, pelicun $RESULT_PEL)"
exit $STATUS
