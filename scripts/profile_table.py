#!/usr/bin/env python3
"""The table of scripts/profile.sh: callgrind's instruction counts of a
`rockfrag run`, per analysis, by stage.

Usage: profile_table.py CALLGRIND_FILE ANALYSES

Stages are the inclusive counts of the functions that do them (each
counted once: none of them calls another), read through callgrind_annotate.
The solver's share is split by the source file (and, for the Taylor
series, the function) of each inlined line, from its exclusive counts: the
compiler inlines most of the solver into a few functions, but callgrind
still knows which source line each instruction came from. What the solver
spends in functions of other files (libm through detmath.rs, memcpy) is
its "math library" row.
"""
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
ROW = re.compile(r"^\s*([\d,]+) \(\s*[\d.]+%\)\s+(.*)$")


def annotate(path, *args):
    out = subprocess.run(
        ["callgrind_annotate", "--threshold=100", "--auto=no", *args, path],
        check=True, capture_output=True, text=True).stdout
    return out


def entries(text):
    """(count, file, function, real) of each file:function line; `real`
    when the function is a symbol of its own (callgrind names its object)."""
    rows = []
    for line in text.splitlines():
        if line.startswith("-- ") and "annotated" in line:
            break
        m = ROW.match(line)
        if not m or "PROGRAM TOTALS" in line:
            continue
        count = int(m.group(1).replace(",", ""))
        rest = m.group(2)
        real = rest.endswith("]") and " [" in rest
        if real:
            rest = rest[:rest.rindex(" [")]
        file, _, function = rest.partition(":")
        rows.append((count, file, function, real))
    return rows


def called_from(path, callee, caller):
    """The inclusive count of `callee` (a function-name pattern) called from
    functions matching `caller`, from callgrind_annotate's caller tree."""
    out = subprocess.run(
        ["callgrind_annotate", "--threshold=100", "--auto=no", "--inclusive=yes",
         "--tree=caller", path], check=True, capture_output=True, text=True).stdout
    callee_rx, caller_rx = re.compile(callee), re.compile(caller)
    arcs, total_count = [], 0
    for line in out.splitlines():
        m = re.match(r"^\s*([\d,]+) \(\s*[\d.]+%\)\s+([<*])\s+(.*)$", line)
        if not m:
            continue
        count, kind, name = int(m.group(1).replace(",", "")), m.group(2), m.group(3)
        function = name.split(" [")[0].split(" (")[0].partition(":")[2]
        if kind == "<":
            arcs.append((count, function))
        else:
            if callee_rx.search(function) and name.rstrip().endswith("]"):
                total_count += sum(c for c, f in arcs if caller_rx.search(f))
            arcs = []
    return total_count


def total(text):
    for line in text.splitlines():
        if "PROGRAM TOTALS" in line:
            return int(line.split()[0].replace(",", ""))
    raise SystemExit("no PROGRAM TOTALS in callgrind_annotate's output")


def inclusive(rows, pattern):
    """Sum of the inclusive counts of the real functions matching `pattern`."""
    rx = re.compile(pattern)
    return sum(c for c, _, f, real in rows if real and rx.search(f))


def taylor_functions():
    """Line number -> name of the function of src/solver/taylor.rs."""
    names, current = {}, "?"
    for i, line in enumerate((ROOT / "src/solver/taylor.rs").read_text().splitlines(), 1):
        m = re.match(r"\s*(?:pub(?:\([a-z]+\))? )?(?:const )?fn ([a-z_0-9]+)", line)
        if m:
            current = m.group(1)
        names[i] = current
    return names


def taylor_lines(path):
    """Exclusive counts of src/solver/taylor.rs by line."""
    out = subprocess.run(
        ["callgrind_annotate", "--auto=yes", "--show-percs=no", "--context=0",
         "--threshold=100", path], capture_output=True, text=True).stdout
    counts, inside, line_no = {}, False, None
    for line in out.splitlines():
        if line.startswith("-- Auto-annotated source:"):
            inside = line.rstrip().endswith("src/solver/taylor.rs")
            line_no = 0
            continue
        if not inside:
            continue
        if line.startswith("-- line "):
            line_no = int(re.findall(r"\d+", line)[0]) - 1
            continue
        m = re.match(r"^\s*([\d,]+|\.)\s", line)
        if m is None or line_no is None:
            continue
        line_no += 1
        if m.group(1) != ".":
            counts[line_no] = counts.get(line_no, 0) + int(m.group(1).replace(",", ""))
    return counts


SOLVER_FILES = [
    ("event searches (scan.rs, roots.rs: first descent, Newton, Brent)",
     ("solver/scan.rs", "solver/roots.rs")),
    ("impacts and the cascade and chatter rules (impact.rs, impacts.rs, cascade.rs, chatter.rs)",
     ("solver/impact.rs", "driver/impacts.rs", "driver/cascade.rs",
      "driver/chatter.rs")),
    ("flight and its landing searches (flight.rs)", ("driver/flight.rs",)),
    ("rock steps: the step loop, event checks on the series, θmax, μ demand (rock.rs)",
     ("driver/rock.rs",)),
    ("contact forces and kinematics (physics.rs, block.rs)",
     ("solver/physics.rs", "solver/block.rs")),
]
TAYLOR = {
    "Taylor series: coefficients and step size": ("new", "trig_term", "conv", "step"),
    "Taylor series: dense output (ψ, ψ̇, sin φ, cos φ at a time)": ("at", "full_at", "eval"),
    "Taylor series: ψ range and curvature bounds": ("psi_bounds", "curvature_bound"),
}


def main():
    path, analyses = sys.argv[1], int(sys.argv[2])
    incl_text = annotate(path, "--inclusive=yes")
    excl_text = annotate(path)
    incl = entries(incl_text)
    excl = entries(excl_text)
    grand = total(excl_text)

    # the members' synthesis and filter, once each before the analyses
    # (Source::prepare; the spectrum figure makes records again, counted
    # with the figures)
    # (its parallel loop runs on rayon's pool, outside Source::prepare's own
    # count): every synthesis but those of Synthesizer::generate
    synthesis = inclusive(incl, r"Synthesizer::natural_into$") - called_from(
        path, r"Synthesizer::natural_into$", r"Synthesizer::generate$")
    motion = inclusive(incl, r"study::source::Source::motion$")
    solver = inclusive(incl, r"solver::driver::simulate$")
    rows_csv = inclusive(incl, r"Columns>::write_row$") + inclusive(incl, r"Columns>::row$")
    load_figures = inclusive(incl, r"StudyData::load_pooled$")
    load_fit = inclusive(incl, r"fragility::data::read_outcomes_for$")
    reading = inclusive(incl, r"tally::Tally::read$") + load_fit + load_figures
    # the fit's cases run on rayon's pool, outside fit_and_write's own count
    fit_and_write = inclusive(incl, r"fragility::report::fit_and_write$")
    fit_files = inclusive(incl, r"fragility::files::write_outputs$")
    fit = inclusive(incl, r"fragility::case::fit_case$") + fit_and_write - load_fit - fit_files
    summary = inclusive(incl, r"study::write_summary$")
    figures = inclusive(incl, r"pipeline::finish$") - fit_and_write - summary - load_figures

    # the solver's own lines, by source file
    in_solver = [(c, fi) for c, fi, f, _ in excl if "solver::" in f]
    parts = []
    taylor = taylor_lines(path)
    names = taylor_functions()
    for label, fns in TAYLOR.items():
        parts.append((label, sum(c for ln, c in taylor.items() if names.get(ln) in fns)))
    taylor_other = sum(c for c, fi in in_solver if fi.endswith("solver/taylor.rs")) - sum(
        p for _, p in parts)
    for label, files in SOLVER_FILES:
        parts.append((label, sum(c for c, fi in in_solver if fi.endswith(files))))
    known = tuple(f for _, fs in SOLVER_FILES for f in fs) + ("solver/taylor.rs",)
    loop = sum(c for c, fi in in_solver if not fi.endswith(known)) + taylor_other
    parts.append(("event loop and bookkeeping (driver/mod.rs, events.rs, bookkeeping.rs, "
                  "rest.rs, slide.rs; core's f64 helpers)", loop))
    own = sum(c for c, _ in in_solver)
    parts.append(("math library called by the solver (sin, cos, exp through detmath)",
                  solver - own))

    table = [
        ("**records**", synthesis + motion),
        ("  synthesis: phases, inverse FFT, envelope, high-pass filter, once a member "
         "(Source::prepare)", synthesis),
        ("  every unit: scaling to the level and integration; without kept members, "
         "synthesis too (Source::motion)", motion),
        ("**the solver**", solver),
    ] + [("  " + label, c) for label, c in parts] + [
        ("CSV rows: formatting the outcomes", rows_csv),
        ("reading outcomes.csv back (tally, fit, figures)", reading),
        ("fit and bootstrap", fit),
        ("fit files (fragility*.csv, .xml)", fit_files),
        ("figures (less their reading)", figures),
        ("summary.md", summary),
    ]
    counted = synthesis + motion + solver + rows_csv + reading + fit + fit_files + figures + summary
    table.append(("other (start, spec, threads, checkpoints)", grand - counted))
    print(f"{analyses} analyses, {grand:,} instructions, "
          f"{grand / analyses:,.0f} per analysis\n")
    print("| stage | instructions per analysis | share |")
    print("|---|---:|---:|")
    for label, c in table:
        name = label.strip()
        name = ("&nbsp;&nbsp;" + name) if label.startswith("  ") else name
        print(f"| {name} | {c / analyses:,.0f} | {100 * c / grand:.1f} % |")


if __name__ == "__main__":
    main()
