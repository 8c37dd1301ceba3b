set terminal pngcairo size 1000,650 noenhanced font "sans,10"
set output "accuracy_hydrostatic.png.tmp"
$wcsph << EOD
4.00007 0.0174573 "10mm f=1 plain"
5.32746 0.0183711 "10mm f=1 corrected"
19.3963 0.010646 "6.67mm f=1 plain"
20.4933 0.00978987 "5mm f=2 plain"
26.8242 0.010115 "5mm f=2 corrected"
27.9418 0.0140564 "6.67mm f=1 corrected"
46.9325 0.0104937 "5mm f=1 plain"
61.6914 0.00988709 "5mm f=1 corrected"
EOD
$wcsphfront << EOD
4.00007 0.0174573 "10mm f=1 plain"
19.3963 0.010646 "6.67mm f=1 plain"
20.4933 0.00978987 "5mm f=2 plain"
EOD
$dfsph << EOD
1.71402 0.0236398 "10mm f=1"
6.82006 0.0101812 "5mm f=2"
7.28719 0.0133013 "6.67mm f=1"
12.9975 0.0125715 "5mm f=1"
EOD
$dfsphfront << EOD
1.71402 0.0236398 "10mm f=1"
6.82006 0.0101812 "5mm f=2"
EOD
set logscale xy
set grid
set title "Hydrostatic column: WCSPH and DFSPH"
set xlabel "wall time (s), AMD EPYC"
set ylabel "RMS pressure error / rho0 g H (log)"
set key outside right top
set offsets graph 0.05, graph 0.25, graph 0.1, graph 0.1
plot $wcsph using 1:2 with points pt 7 ps 1.3 lc rgb "#d62728" title "wcsph: RMS pressure error / rho0 g H", \
     $wcsphfront using 1:2 with linespoints lw 2 dt 1 pt 6 ps 2.2 lc rgb "#d62728" title "wcsph: its Pareto front", \
     $wcsph using 1:2:3 with labels left offset 0.6,0.5 rotate by 40 font "sans,8" tc rgb "#d62728" notitle, \
     $dfsph using 1:2 with points pt 9 ps 1.3 lc rgb "#1f77b4" title "dfsph: RMS pressure error / rho0 g H", \
     $dfsphfront using 1:2 with linespoints lw 2 dt 1 pt 8 ps 2.2 lc rgb "#1f77b4" title "dfsph: its Pareto front", \
     $dfsph using 1:2:3 with labels left offset 0.6,0.5 rotate by 40 font "sans,8" tc rgb "#1f77b4" notitle
