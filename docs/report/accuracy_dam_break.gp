set terminal pngcairo size 1000,650 noenhanced font "sans,10"
set output "accuracy_dam_break.png.tmp"
$wcsph << EOD
0.403256 0.286489 "a/8 f=2"
0.709562 0.288473 "a/8 f=1"
2.72481 0.261634 "a/12 f=1"
4.66166 0.266297 "a/16 f=2"
10.147 0.263309 "a/16 f=1"
20.681 0.264572 "a/16 f=0.5"
21.7597 0.256224 "a/24 f=2"
43.1055 0.259907 "a/24 f=1"
68.0962 0.252137 "a/32 f=2"
134.051 0.253154 "a/32 f=1"
EOD
$wcsphfront << EOD
0.403256 0.286489 "a/8 f=2"
2.72481 0.261634 "a/12 f=1"
21.7597 0.256224 "a/24 f=2"
68.0962 0.252137 "a/32 f=2"
EOD
$dfsph << EOD
0.205272 0.276047 "a/8 f=2"
0.255451 0.300249 "a/8 f=1"
0.865358 0.286668 "a/12 f=1"
2.14352 0.276738 "a/16 f=2"
2.29315 0.281898 "a/16 f=1"
4.21011 0.287374 "a/16 f=0.5"
10.8642 0.269309 "a/24 f=1"
11.5657 0.261956 "a/24 f=2"
35.6376 0.250933 "a/32 f=1"
39.0987 0.256155 "a/32 f=2"
EOD
$dfsphfront << EOD
0.205272 0.276047 "a/8 f=2"
10.8642 0.269309 "a/24 f=1"
11.5657 0.261956 "a/24 f=2"
35.6376 0.250933 "a/32 f=1"
EOD
$wcsphalt << EOD
0.403256 0.0802209 "a/8 f=2"
0.709562 0.0835921 "a/8 f=1"
2.72481 0.0564335 "a/12 f=1"
4.66166 0.0622479 "a/16 f=2"
10.147 0.0604732 "a/16 f=1"
20.681 0.0593735 "a/16 f=0.5"
21.7597 0.0543659 "a/24 f=2"
43.1055 0.0557457 "a/24 f=1"
68.0962 0.052158 "a/32 f=2"
134.051 0.0526845 "a/32 f=1"
EOD
$wcsphaltfront << EOD
0.403256 0.0802209 "a/8 f=2"
2.72481 0.0564335 "a/12 f=1"
21.7597 0.0543659 "a/24 f=2"
68.0962 0.052158 "a/32 f=2"
EOD
$dfsphalt << EOD
0.205272 0.0735538 "a/8 f=2"
0.255451 0.0876713 "a/8 f=1"
0.865358 0.0796657 "a/12 f=1"
2.14352 0.0734007 "a/16 f=2"
2.29315 0.0787009 "a/16 f=1"
4.21011 0.08862 "a/16 f=0.5"
10.8642 0.0680994 "a/24 f=1"
11.5657 0.0633879 "a/24 f=2"
35.6376 0.0555782 "a/32 f=1"
39.0987 0.0591272 "a/32 f=2"
EOD
$dfsphaltfront << EOD
0.205272 0.0735538 "a/8 f=2"
2.14352 0.0734007 "a/16 f=2"
10.8642 0.0680994 "a/24 f=1"
11.5657 0.0633879 "a/24 f=2"
35.6376 0.0555782 "a/32 f=1"
EOD
set logscale xy
set grid
set title "Dam break against Martin & Moyce (1952): WCSPH and DFSPH"
set xlabel "wall time (s), AMD EPYC"
set ylabel "RMS error of Z = x/a (log)"
set key outside right top
set offsets graph 0.05, graph 0.25, graph 0.1, graph 0.1
plot $wcsph using 1:2 with points pt 7 ps 1.3 lc rgb "#d62728" title "wcsph: RMS error of Z = x/a", \
     $wcsphfront using 1:2 with linespoints lw 2 dt 1 pt 6 ps 2.2 lc rgb "#d62728" title "wcsph: its Pareto front", \
     $wcsph using 1:2:3 with labels left offset 0.6,0.5 rotate by 40 font "sans,8" tc rgb "#d62728" notitle, \
     $dfsph using 1:2 with points pt 9 ps 1.3 lc rgb "#1f77b4" title "dfsph: RMS error of Z = x/a", \
     $dfsphfront using 1:2 with linespoints lw 2 dt 1 pt 8 ps 2.2 lc rgb "#1f77b4" title "dfsph: its Pareto front", \
     $dfsph using 1:2:3 with labels left offset 0.6,0.5 rotate by 40 font "sans,8" tc rgb "#1f77b4" notitle, \
     $wcsphalt using 1:2 with points pt 5 ps 1.3 lc rgb "#ff7f0e" title "wcsph: RMS error of Z, time shifted by 0.175", \
     $wcsphaltfront using 1:2 with linespoints lw 2 dt 2 pt 4 ps 2.2 lc rgb "#ff7f0e" title "wcsph: its Pareto front", \
     $wcsphalt using 1:2:3 with labels right offset -0.6,-0.5 rotate by 40 font "sans,8" tc rgb "#ff7f0e" notitle, \
     $dfsphalt using 1:2 with points pt 13 ps 1.3 lc rgb "#17becf" title "dfsph: RMS error of Z, time shifted by 0.175", \
     $dfsphaltfront using 1:2 with linespoints lw 2 dt 2 pt 12 ps 2.2 lc rgb "#17becf" title "dfsph: its Pareto front", \
     $dfsphalt using 1:2:3 with labels right offset -0.6,-0.5 rotate by 40 font "sans,8" tc rgb "#17becf" notitle
