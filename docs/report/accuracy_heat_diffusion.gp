set terminal pngcairo size 900,600 noenhanced font "sans,10"
set output "accuracy_heat_diffusion.png.tmp"
$all << EOD
0.0207545 0.00268666 "20mm f=1"
0.0524968 0.00299748 "10mm f=2"
0.165158 0.00331173 "10mm f=1"
0.448718 0.00355883 "10mm f=0.25"
0.776071 0.00321774 "6.67mm f=1"
1.18776 0.0023688 "5mm f=2"
3.06107 0.00244818 "5mm f=1"
8.46823 0.00199118 "4mm f=1"
12.3855 0.00250876 "5mm f=0.25"
EOD
$front << EOD
0.0207545 0.00268666 "20mm f=1"
1.18776 0.0023688 "5mm f=2"
8.46823 0.00199118 "4mm f=1"
EOD
set logscale xy
set grid
set title "Heat diffusion across a plane against erf"
set xlabel "wall time (s), AMD EPYC"
set ylabel "RMS temperature error (unit step) (log)"
set key top right
set offsets graph 0.05, graph 0.25, graph 0.1, graph 0.1
plot $all using 1:2 with points pt 7 ps 1.3 lc rgb "#7f7f7f" title "RMS temperature error (unit step)", \
     $front using 1:2 with linespoints lw 2 pt 6 ps 2.2 lc rgb "#d62728" title "Pareto front", \
     $all using 1:2:3 with labels left offset 0.6,0.5 rotate by 40 font "sans,8" notitle
