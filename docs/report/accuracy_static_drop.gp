set terminal pngcairo size 1000,650 noenhanced font "sans,10"
set output "accuracy_static_drop.png.tmp"
$wcsph << EOD
0.629537 0.211241 "10mm f=2"
0.859778 0.31411 "12.5mm f=1"
2.1702 0.59358 "10mm f=1"
6.36706 0.824591 "7.5mm f=1"
13.0871 1.54855 "5mm f=2"
26.733 1.70652 "5mm f=1"
EOD
$wcsphfront << EOD
0.629537 0.211241 "10mm f=2"
EOD
$dfsph << EOD
0.448609 0.241405 "12.5mm f=1"
0.599093 0.0219898 "10mm f=2"
0.933093 0.0145537 "10mm f=1"
1.95883 0.212911 "7.5mm f=1"
7.08211 0.182435 "5mm f=1"
7.19048 0.160786 "5mm f=2"
EOD
$dfsphfront << EOD
0.448609 0.241405 "12.5mm f=1"
0.599093 0.0219898 "10mm f=2"
0.933093 0.0145537 "10mm f=1"
EOD
$wcsphalt << EOD
EOD
$wcsphaltfront << EOD
EOD
$dfsphalt << EOD
0.448609 0.080774 "12.5mm f=1"
0.599093 0.072645 "10mm f=2"
0.933093 0.0685115 "10mm f=1"
1.95883 0.0200986 "7.5mm f=1"
7.08211 0.0517906 "5mm f=1"
7.19048 0.0329395 "5mm f=2"
EOD
$dfsphaltfront << EOD
0.448609 0.080774 "12.5mm f=1"
0.599093 0.072645 "10mm f=2"
0.933093 0.0685115 "10mm f=1"
1.95883 0.0200986 "7.5mm f=1"
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
