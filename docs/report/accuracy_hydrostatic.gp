set terminal pngcairo size 900,600 noenhanced font "sans,10"
set output "accuracy_hydrostatic.png.tmp"
$all << EOD
7.59132 0.0361848 "10mm f=1 plain"
9.77312 0.0124188 "10mm f=1 corrected"
31.9444 0.030429 "6.67mm f=1 plain"
41.2932 0.0197381 "5mm f=2 plain"
42.853 0.00679696 "6.67mm f=1 corrected"
55.5669 0.00420454 "5mm f=2 corrected"
79.0956 0.0205954 "5mm f=1 plain"
111.086 0.00864525 "5mm f=1 corrected"
EOD
$front << EOD
7.59132 0.0361848 "10mm f=1 plain"
9.77312 0.0124188 "10mm f=1 corrected"
42.853 0.00679696 "6.67mm f=1 corrected"
55.5669 0.00420454 "5mm f=2 corrected"
EOD
set logscale xy
set grid
set title "Hydrostatic column"
set xlabel "wall time (s), AMD EPYC"
set ylabel "RMS pressure error / rho0 g H (log)"
set key top right
set offsets graph 0.05, graph 0.25, graph 0.1, graph 0.1
plot $all using 1:2 with points pt 7 ps 1.3 lc rgb "#7f7f7f" title "RMS pressure error / rho0 g H", \
     $front using 1:2 with linespoints lw 2 pt 6 ps 2.2 lc rgb "#d62728" title "Pareto front", \
     $all using 1:2:3 with labels left offset 0.6,0.5 rotate by 40 font "sans,8" notitle
