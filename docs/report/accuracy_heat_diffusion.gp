set terminal pngcairo size 1000,650 noenhanced font "sans,10"
set output "accuracy_heat_diffusion.png.tmp"
$wcsph << EOD
0.0099937 0.00368371 "20mm f=1"
0.0329774 0.00484507 "10mm f=2"
0.0667484 0.00517526 "10mm f=1"
0.254901 0.00543097 "10mm f=0.25"
0.277033 0.00505468 "6.67mm f=1"
0.590915 0.00374289 "5mm f=2"
1.16218 0.00382728 "5mm f=1"
3.62257 0.00310536 "4mm f=1"
4.54818 0.00389131 "5mm f=0.25"
EOD
$wcsphfront << EOD
0.0099937 0.00368371 "20mm f=1"
3.62257 0.00310536 "4mm f=1"
EOD
$dfsph << EOD
0.0193012 0.00369402 "20mm f=1"
0.066196 0.00484507 "10mm f=2"
0.134256 0.00517527 "10mm f=1"
0.538318 0.00505482 "6.67mm f=1"
0.542827 0.00543097 "10mm f=0.25"
1.15097 0.0037429 "5mm f=2"
2.33691 0.00382728 "5mm f=1"
7.37107 0.00310538 "4mm f=1"
9.04778 0.00389131 "5mm f=0.25"
EOD
$dfsphfront << EOD
0.0193012 0.00369402 "20mm f=1"
7.37107 0.00310538 "4mm f=1"
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
