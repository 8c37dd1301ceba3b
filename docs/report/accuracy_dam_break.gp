set terminal pngcairo size 900,600 noenhanced font "sans,10"
set output "accuracy_dam_break.png.tmp"
$all << EOD
0.520889 0.18422 "a/8 f=2"
1.34626 0.196514 "a/8 f=1"
7.10878 0.212039 "a/12 f=1"
8.46416 0.244396 "a/16 f=2"
23.8055 0.234423 "a/16 f=1"
36.5903 0.238662 "a/16 f=0.5"
39.484 0.240289 "a/24 f=2"
130.92 0.236196 "a/24 f=1"
137.307 0.233392 "a/32 f=2"
275.809 0.23494 "a/32 f=1"
EOD
$front << EOD
0.520889 0.18422 "a/8 f=2"
EOD
$alt << EOD
0.520889 0.0444968 "a/8 f=2"
1.34626 0.0338828 "a/8 f=1"
7.10878 0.033241 "a/12 f=1"
8.46416 0.0439533 "a/16 f=2"
23.8055 0.0386181 "a/16 f=1"
36.5903 0.0398785 "a/16 f=0.5"
39.484 0.0401547 "a/24 f=2"
130.92 0.0377999 "a/24 f=1"
137.307 0.0378923 "a/32 f=2"
275.809 0.038448 "a/32 f=1"
EOD
$altfront << EOD
0.520889 0.0444968 "a/8 f=2"
1.34626 0.0338828 "a/8 f=1"
7.10878 0.033241 "a/12 f=1"
EOD
set logscale xy
set grid
set title "Dam break against Martin & Moyce (1952)"
set xlabel "wall time (s), AMD EPYC"
set ylabel "RMS error of Z = x/a (log)"
set key top right
set offsets graph 0.05, graph 0.25, graph 0.1, graph 0.1
plot $all using 1:2 with points pt 7 ps 1.3 lc rgb "#7f7f7f" title "RMS error of Z = x/a", \
     $front using 1:2 with linespoints lw 2 pt 6 ps 2.2 lc rgb "#d62728" title "Pareto front", \
     $all using 1:2:3 with labels left offset 0.6,0.5 rotate by 40 font "sans,8" notitle, \
     $alt using 1:2 with points pt 5 ps 1.1 lc rgb "#1f77b4" title "RMS error of Z, time shifted by 0.175", \
     $altfront using 1:2 with linespoints lw 2 pt 4 ps 2.0 lc rgb "#1f77b4" dt 2 title "its Pareto front", \
     $alt using 1:2:3 with labels right offset -0.6,-0.5 rotate by 40 font "sans,8" tc rgb "#1f77b4" notitle
