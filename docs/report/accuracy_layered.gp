set terminal pngcairo size 1000,650 noenhanced font "sans,10"
set output "accuracy_layered.png.tmp"
$wcsph << EOD
9.43014 0.00555556 "10mm f=1 mass"
9.718 0.00185185 "10mm f=1 reference"
10.4548 0.0240741 "10mm f=1 number"
38.7336 0.00109739 "6.67mm f=1 reference"
38.9544 0.00823045 "6.67mm f=1 mass"
40.0046 0.048011 "6.67mm f=1 number"
45.0394 0.018287 "5mm f=2 mass"
47.2501 0.00138889 "5mm f=2 reference"
47.3759 0.0510417 "5mm f=2 number"
89.5279 0.0185185 "5mm f=1 mass"
98.8328 0.0685185 "5mm f=1 number"
99.1355 0.00416667 "5mm f=1 reference"
EOD
$wcsphfront << EOD
9.43014 0.00555556 "10mm f=1 mass"
9.718 0.00185185 "10mm f=1 reference"
38.7336 0.00109739 "6.67mm f=1 reference"
EOD
$dfsph << EOD
4.42023 0.000192901 "10mm f=1 reference: error = 0"
5.20022 0.37037 "10mm f=1 number"
6.80937 0.193519 "10mm f=1 mass"
13.7196 0.000192901 "6.67mm f=1 reference: error = 0"
14.6212 0.951715 "6.67mm f=1 number"
21.458 0.000578704 "5mm f=2 reference"
22.1035 0.159396 "6.67mm f=1 mass"
27.5131 0.963889 "5mm f=1 number"
27.8658 0.00416667 "5mm f=1 reference"
33.654 0.391782 "5mm f=1 mass"
36.0603 0.962963 "5mm f=2 number"
39.2577 0.943056 "5mm f=2 mass"
EOD
$dfsphfront << EOD
4.42023 0.000192901 "10mm f=1 reference: error = 0"
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
