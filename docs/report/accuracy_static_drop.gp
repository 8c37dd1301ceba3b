set terminal pngcairo size 1000,650 noenhanced font "sans,10"
set output "accuracy_static_drop.png.tmp"
$wcsph << EOD
0.510787 0.211241 "10mm f=2"
0.816906 0.31411 "12.5mm f=1"
1.88016 0.59358 "10mm f=1"
5.51098 0.824591 "7.5mm f=1"
12.6145 1.54855 "5mm f=2"
24.7381 1.70652 "5mm f=1"
EOD
$wcsphfront << EOD
0.510787 0.211241 "10mm f=2"
EOD
$dfsph << EOD
0.38048 0.358291 "12.5mm f=1"
0.689609 0.254779 "10mm f=2"
0.808088 0.589982 "10mm f=1"
2.30956 0.535595 "7.5mm f=1"
13.0133 0.958545 "5mm f=1"
13.4356 0.71707 "5mm f=2"
EOD
$dfsphfront << EOD
0.38048 0.358291 "12.5mm f=1"
0.689609 0.254779 "10mm f=2"
EOD
$wcsphalt << EOD
EOD
$wcsphaltfront << EOD
EOD
$dfsphalt << EOD
0.38048 0.357975 "12.5mm f=1"
0.808088 0.348557 "10mm f=1"
2.30956 0.418838 "7.5mm f=1"
13.0133 0.306235 "5mm f=1"
EOD
$dfsphaltfront << EOD
0.38048 0.357975 "12.5mm f=1"
0.808088 0.348557 "10mm f=1"
13.0133 0.306235 "5mm f=1"
EOD
set logscale xy
set grid
set title "A free drop against Laplace and Rayleigh: WCSPH and DFSPH"
set xlabel "wall time (s), AMD EPYC"
set ylabel "|interior pressure / (2 sigma / R) - 1| (log)"
set key outside right top
set offsets graph 0.05, graph 0.25, graph 0.1, graph 0.1
plot $wcsph using 1:2 with points pt 7 ps 1.3 lc rgb "#d62728" title "wcsph: |interior pressure / (2 sigma / R) - 1|", \
     $wcsphfront using 1:2 with linespoints lw 2 dt 1 pt 6 ps 2.2 lc rgb "#d62728" title "wcsph: its Pareto front", \
     $wcsph using 1:2:3 with labels left offset 0.6,0.5 rotate by 40 font "sans,8" tc rgb "#d62728" notitle, \
     $dfsph using 1:2 with points pt 9 ps 1.3 lc rgb "#1f77b4" title "dfsph: |interior pressure / (2 sigma / R) - 1|", \
     $dfsphfront using 1:2 with linespoints lw 2 dt 1 pt 8 ps 2.2 lc rgb "#1f77b4" title "dfsph: its Pareto front", \
     $dfsph using 1:2:3 with labels left offset 0.6,0.5 rotate by 40 font "sans,8" tc rgb "#1f77b4" notitle, \
     $wcsphalt using 1:2 with points pt 5 ps 1.3 lc rgb "#ff7f0e" title "wcsph: |period / Rayleigh's - 1|", \
     $wcsphaltfront using 1:2 with linespoints lw 2 dt 2 pt 4 ps 2.2 lc rgb "#ff7f0e" title "wcsph: its Pareto front", \
     $wcsphalt using 1:2:3 with labels right offset -0.6,-0.5 rotate by 40 font "sans,8" tc rgb "#ff7f0e" notitle, \
     $dfsphalt using 1:2 with points pt 13 ps 1.3 lc rgb "#17becf" title "dfsph: |period / Rayleigh's - 1|", \
     $dfsphaltfront using 1:2 with linespoints lw 2 dt 2 pt 12 ps 2.2 lc rgb "#17becf" title "dfsph: its Pareto front", \
     $dfsphalt using 1:2:3 with labels right offset -0.6,-0.5 rotate by 40 font "sans,8" tc rgb "#17becf" notitle
