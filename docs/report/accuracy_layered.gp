set terminal pngcairo size 1000,650 noenhanced font "sans,10"
set output "accuracy_layered.png.tmp"
$wcsph << EOD
6.87551 0.0240741 "10mm f=1 number"
7.43976 0.00555556 "10mm f=1 mass"
35.1496 0.00823045 "6.67mm f=1 mass"
36.7398 0.048011 "6.67mm f=1 number"
46.0137 0.0510417 "5mm f=2 number"
47.2133 0.018287 "5mm f=2 mass"
79.8391 0.0185185 "5mm f=1 mass"
79.9321 0.0685185 "5mm f=1 number"
EOD
$wcsphfront << EOD
6.87551 0.0240741 "10mm f=1 number"
7.43976 0.00555556 "10mm f=1 mass"
EOD
$dfsph << EOD
4.1223 0.37037 "10mm f=1 number"
5.23703 0.193519 "10mm f=1 mass"
11.9511 0.951715 "6.67mm f=1 number"
17.8071 0.159396 "6.67mm f=1 mass"
26.3276 0.963889 "5mm f=1 number"
30.4489 0.391782 "5mm f=1 mass"
41.5937 0.962963 "5mm f=2 number"
44.7163 0.943056 "5mm f=2 mass"
EOD
$dfsphfront << EOD
4.1223 0.37037 "10mm f=1 number"
5.23703 0.193519 "10mm f=1 mass"
17.8071 0.159396 "6.67mm f=1 mass"
EOD
set logscale xy
set grid
set title "Two fluids layered (Rayleigh-Taylor overturn): WCSPH and DFSPH"
set xlabel "wall time (s), AMD EPYC"
set ylabel "mass on the wrong side / total mass (log)"
set key outside right top
set offsets graph 0.05, graph 0.25, graph 0.1, graph 0.1
plot $wcsph using 1:2 with points pt 7 ps 1.3 lc rgb "#d62728" title "wcsph: mass on the wrong side / total mass", \
     $wcsphfront using 1:2 with linespoints lw 2 dt 1 pt 6 ps 2.2 lc rgb "#d62728" title "wcsph: its Pareto front", \
     $wcsph using 1:2:3 with labels left offset 0.6,0.5 rotate by 40 font "sans,8" tc rgb "#d62728" notitle, \
     $dfsph using 1:2 with points pt 9 ps 1.3 lc rgb "#1f77b4" title "dfsph: mass on the wrong side / total mass", \
     $dfsphfront using 1:2 with linespoints lw 2 dt 1 pt 8 ps 2.2 lc rgb "#1f77b4" title "dfsph: its Pareto front", \
     $dfsph using 1:2:3 with labels left offset 0.6,0.5 rotate by 40 font "sans,8" tc rgb "#1f77b4" notitle
