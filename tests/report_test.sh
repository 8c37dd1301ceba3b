#!/usr/bin/env bash
# The report command end to end on its quick ladder: every CSV with its header and rows (both
# pressure solvers in each), every plot a non-empty PNG, pages that name the machine, bad
# arguments refused.
set -euo pipefail
bin=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

"$bin" report accuracy --quick --out "$work" 2> "$work/accuracy.log" || fail "report accuracy: $(tail -20 "$work/accuracy.log")"
"$bin" report stability --quick --out "$work" 2> "$work/stability.log" || fail "report stability: $(tail -20 "$work/stability.log")"

# check_csv FILE HEADER ROWS
check_csv() {
  [ -s "$work/$1" ] || fail "$1 missing or empty"
  [ "$(head -n 1 "$work/$1")" = "$2" ] || fail "$1 header is '$(head -n 1 "$work/$1")'"
  local rows=$(($(wc -l < "$work/$1") - 1))
  [ "$rows" -eq "$3" ] || fail "$1 has $rows rows, expected $3"
}
common=problem,solver,setting,spacing_m,dt_factor,variant,particles,steps,wall_s,cpu_s,load_1min,error
check_csv accuracy_dam_break.csv "$common,rms_Z_shifted,rms_H,rms_H_shifted,pareto_rms_Z_shifted,pareto,status" 4
check_csv accuracy_hydrostatic.csv "$common,max_bin_ratio_error,bins,pareto,status" 3
check_csv accuracy_heat_diffusion.csv "$common,max_abs_error,pareto,status" 4
check_csv accuracy_layered.csv "$common,heavy_wrong_fraction,light_wrong_fraction,pareto,status" 6
check_csv accuracy_static_drop.csv "$common,period_error,pressure_ratio,period_ratio,largest_Q_over_kick,pareto_period_error,pareto,status" 2
check_csv stability.csv "solver,sweep,case,parameter,value,particles,end_time_s,status,stable,steps,retries,first_trouble_step,first_trouble_time_s,max_density_error,energy_drift,energy_growth_max,lost_particles,largest_body,wall_s,cpu_s,message" 20

for p in dam_break hydrostatic heat_diffusion layered static_drop; do
  for solver in wcsph dfsph; do
    # Every problem has each solver's rungs; the dam break and heat diffusion, which both solvers
    # finish, a point on each solver's own Pareto front (columns pareto, status last; only runs
    # that finished can be on it).
    grep -q "^$p,$solver," "$work/accuracy_$p.csv" || fail "no $solver row in accuracy_$p.csv"
    case $p in dam_break|heat_diffusion)
      grep -q "^$p,$solver,.*,1,ok\$" "$work/accuracy_$p.csv" || fail "no $solver Pareto point in accuracy_$p.csv";;
    esac
  done
  grep -q ',1,ok$' "$work/accuracy_$p.csv" || fail "no Pareto point in accuracy_$p.csv"
done
# The dam break is measured against Martin & Moyce: a finite RMS of Z, not far off, both solvers.
awk -F, 'NR > 1 && !($12 > 0 && $12 < 1) { exit 1 }' "$work/accuracy_dam_break.csv" || fail "dam-break error out of (0, 1): $(cat "$work/accuracy_dam_break.csv")"
# The free drop on DFSPH is measured against Laplace and Rayleigh: its interior pressure within
# 30 % and its period within the issue's 10 % (measured 1.24 and 1.08 at this spacing, the
# coarsest; 0.99 and 1.07 at 1 cm), and only the dam break carries the gate's time-shift note.
awk -F, 'NR > 1 && $2 == "dfsph" && !($14 > 0.7 && $14 < 1.3 && $15 > 0.9 && $15 < 1.1) { exit 1 }' "$work/accuracy_static_drop.csv" || fail "static drop off: $(cat "$work/accuracy_static_drop.csv")"
[ "$(grep -c 'Time shift' "$work/accuracy.md")" -eq 1 ] || fail "the time-shift note is not the dam break's alone"
# The watchdog's verdicts reach the table: the soft case stops with its message, the default holds.
grep -q '^wcsph,stiffness,k=10,.*,stopped,no,.*simulation unstable at step' "$work/stability.csv" || fail "k=10 not reported as stopped"
grep -q '^wcsph,stiffness,k=1000,.*,stable,yes,' "$work/stability.csv" || fail "k=1000 not reported as stable"
for solver in wcsph dfsph; do
  grep -q "^$solver,dt_factor,f=25 no retries,.*,stopped,no,.*solver.cfl" "$work/stability.csv" || fail "$solver dt factor 25 without retries not stopped naming solver.cfl"
  # Every family of sweeps ran on both solvers.
  for sweep in density_ratio viscosity dt_factor temperature spacing surface_tension; do
    grep -q "^$solver,$sweep," "$work/stability.csv" || fail "no $solver $sweep case in stability.csv"
  done
done
# DFSPH's stand-in for the stiffness sweep: its default tolerance holds the drop.
grep -q '^dfsph,density_tolerance,tol=0.0005,.*,stable,yes,' "$work/stability.csv" || fail "DFSPH tol=5e-4 not reported as stable"
# A cube of water with 1 400 times water's surface tension: DFSPH's fitted curvature pulls it into
# one ball (0.976 of its particles in the largest body at 0.1 s; "broke up" under 0.9).
grep -q '^dfsph,surface_tension,sigma=100,.*,stable,yes,' "$work/stability.csv" || fail "DFSPH sigma=100 cube not reported as stable: $(grep surface_tension "$work/stability.csv")"

for png in accuracy_dam_break accuracy_hydrostatic accuracy_heat_diffusion accuracy_layered accuracy_static_drop dam_break_front stability stability_energy; do
  f="$work/$png.png"
  [ -s "$f" ] || fail "$png.png missing or empty"
  [ "$(head -c 8 "$f" | od -An -tx1 | tr -d ' \n')" = "89504e470d0a1a0a" ] || fail "$png.png is not a PNG"
done

model=$(grep -m1 '^model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //')
for page in accuracy.md stability.md; do
  [ -s "$work/$page" ] || fail "$page missing"
  grep -qF "$model" "$work/$page" || fail "$page does not name the CPU '$model'"
  grep -q "hardware threads" "$work/$page" || fail "$page does not give the thread count"
done
grep -q '!\[error against wall time\](accuracy_dam_break.png)' "$work/accuracy.md" || fail "accuracy.md does not show its plot"
grep -q '^| dfsph | a/8 f=1 |' "$work/accuracy.md" || fail "accuracy.md has no DFSPH row"
grep -q 'DFSPH rungs' "$work/accuracy.md" || fail "accuracy.md does not say which rungs DFSPH skips"
grep -q 'wcsph' "$work/accuracy_dam_break.gp" && grep -q 'dfsph' "$work/accuracy_dam_break.gp" || fail "dam-break plot does not draw both solvers"
ls "$work" | grep -q '\.tmp$' && fail "temporary files left behind: $(ls "$work" | grep '\.tmp$')"

status=0
"$bin" report nonsense 2> /dev/null || status=$?
[ "$status" -eq 2 ] || fail "unknown report exited $status, expected 2"
status=0
"$bin" report accuracy --only nothing 2> /dev/null || status=$?
[ "$status" -eq 2 ] || fail "unknown --only name exited $status, expected 2"
echo "report quick ladder: $(grep -c . "$work/accuracy_dam_break.csv") dam-break lines; $(tail -n 1 "$work/accuracy.log")"
