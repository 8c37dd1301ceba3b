set terminal pngcairo size 1000,650 noenhanced font "sans,10"
set output "accuracy_dam_break.png.tmp"
$wcsph << EOD
0.384269 0.286489 "a/8 f=2"
0.70397 0.288473 "a/8 f=1"
2.83606 0.261634 "a/12 f=1"
4.71956 0.266297 "a/16 f=2"
9.23339 0.263309 "a/16 f=1"
21.0077 0.264572 "a/16 f=0.5"
24.3449 0.256224 "a/24 f=2"
40.8498 0.259907 "a/24 f=1"
75.0165 0.252137 "a/32 f=2"
132.866 0.253154 "a/32 f=1"
EOD
$wcsphfront << EOD
0.384269 0.286489 "a/8 f=2"
2.83606 0.261634 "a/12 f=1"
24.3449 0.256224 "a/24 f=2"
75.0165 0.252137 "a/32 f=2"
EOD
$dfsph << EOD
0.206783 0.251388 "a/8 f=2"
0.263155 0.258561 "a/8 f=1"
0.752926 0.281919 "a/12 f=1"
1.86633 0.268144 "a/16 f=2"
2.18109 0.267387 "a/16 f=1"
4.59674 0.275319 "a/16 f=0.5"
9.94791 0.264969 "a/24 f=2"
10.5401 0.263999 "a/24 f=1"
28.8178 0.258342 "a/32 f=2"
38.3295 0.250195 "a/32 f=1"
EOD
$dfsphfront << EOD
0.206783 0.251388 "a/8 f=2"
38.3295 0.250195 "a/32 f=1"
EOD
$wcsphalt << EOD
0.384269 0.0802209 "a/8 f=2"
0.70397 0.0835921 "a/8 f=1"
2.83606 0.0564335 "a/12 f=1"
4.71956 0.0622479 "a/16 f=2"
9.23339 0.0604732 "a/16 f=1"
21.0077 0.0593735 "a/16 f=0.5"
24.3449 0.0543659 "a/24 f=2"
40.8498 0.0557457 "a/24 f=1"
75.0165 0.052158 "a/32 f=2"
132.866 0.0526845 "a/32 f=1"
EOD
$wcsphaltfront << EOD
0.384269 0.0802209 "a/8 f=2"
2.83606 0.0564335 "a/12 f=1"
24.3449 0.0543659 "a/24 f=2"
75.0165 0.052158 "a/32 f=2"
EOD
$dfsphalt << EOD
0.206783 0.0581131 "a/8 f=2"
0.263155 0.0594841 "a/8 f=1"
0.752926 0.0756951 "a/12 f=1"
1.86633 0.0679503 "a/16 f=2"
2.18109 0.064105 "a/16 f=1"
4.59674 0.0767976 "a/16 f=0.5"
9.94791 0.0646803 "a/24 f=2"
10.5401 0.0634827 "a/24 f=1"
28.8178 0.0608647 "a/32 f=2"
38.3295 0.0548401 "a/32 f=1"
EOD
$dfsphaltfront << EOD
0.206783 0.0581131 "a/8 f=2"
38.3295 0.0548401 "a/32 f=1"
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
