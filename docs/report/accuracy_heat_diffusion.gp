set terminal pngcairo size 1000,650 noenhanced font "sans,10"
set output "accuracy_heat_diffusion.png.tmp"
$wcsph << EOD
0.011481 0.00368371 "20mm f=1"
0.0362772 0.00484507 "10mm f=2"
0.0726474 0.00517526 "10mm f=1"
0.279721 0.00543097 "10mm f=0.25"
0.289262 0.00505468 "6.67mm f=1"
0.569553 0.00374289 "5mm f=2"
1.18166 0.00382728 "5mm f=1"
3.6521 0.00310536 "4mm f=1"
4.55635 0.00389131 "5mm f=0.25"
EOD
$wcsphfront << EOD
0.011481 0.00368371 "20mm f=1"
3.6521 0.00310536 "4mm f=1"
EOD
$dfsph << EOD
0.0192753 0.00369402 "20mm f=1"
0.0685871 0.00484507 "10mm f=2"
0.13483 0.00517527 "10mm f=1"
0.532994 0.00505482 "6.67mm f=1"
0.533551 0.00543097 "10mm f=0.25"
1.1429 0.0037429 "5mm f=2"
2.31755 0.00382728 "5mm f=1"
7.39531 0.00310538 "4mm f=1"
8.97758 0.00389131 "5mm f=0.25"
EOD
$dfsphfront << EOD
0.0192753 0.00369402 "20mm f=1"
7.39531 0.00310538 "4mm f=1"
EOD
set logscale xy
set grid
set title "Heat diffusion across a plane against erf: WCSPH and DFSPH"
set xlabel "wall time (s), AMD EPYC"
set ylabel "RMS temperature error (unit step) (log)"
set key outside right top
set offsets graph 0.05, graph 0.25, graph 0.1, graph 0.1
plot $wcsph using 1:2 with points pt 7 ps 1.3 lc rgb "#d62728" title "wcsph: RMS temperature error (unit step)", \
     $wcsphfront using 1:2 with linespoints lw 2 dt 1 pt 6 ps 2.2 lc rgb "#d62728" title "wcsph: its Pareto front", \
     $wcsph using 1:2:3 with labels left offset 0.6,0.5 rotate by 40 font "sans,8" tc rgb "#d62728" notitle, \
     $dfsph using 1:2 with points pt 9 ps 1.3 lc rgb "#1f77b4" title "dfsph: RMS temperature error (unit step)", \
     $dfsphfront using 1:2 with linespoints lw 2 dt 1 pt 8 ps 2.2 lc rgb "#1f77b4" title "dfsph: its Pareto front", \
     $dfsph using 1:2:3 with labels left offset 0.6,0.5 rotate by 40 font "sans,8" tc rgb "#1f77b4" notitle
