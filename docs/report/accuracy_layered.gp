set terminal pngcairo size 900,600 noenhanced font "sans,10"
set output "accuracy_layered.png.tmp"
$all << EOD
11.5022 0.012963 "10mm f=1 number"
50.697 0.0255144 "6.67mm f=1 number"
73.3513 0.0460648 "5mm f=2 number"
77.3369 0.00358796 "5mm f=2 mass"
124.025 0.00925926 "5mm f=1 mass"
138.56 0.0668981 "5mm f=1 number"
EOD
$front << EOD
11.5022 0.012963 "10mm f=1 number"
77.3369 0.00358796 "5mm f=2 mass"
EOD
set logscale xy
set grid
set title "Two fluids layered (Rayleigh-Taylor overturn)"
set xlabel "wall time (s), AMD EPYC"
set ylabel "mass on the wrong side / total mass (log)"
set key top right
set offsets graph 0.05, graph 0.25, graph 0.1, graph 0.1
plot $all using 1:2 with points pt 7 ps 1.3 lc rgb "#7f7f7f" title "mass on the wrong side / total mass", \
     $front using 1:2 with linespoints lw 2 pt 6 ps 2.2 lc rgb "#d62728" title "Pareto front", \
     $all using 1:2:3 with labels left offset 0.6,0.5 rotate by 40 font "sans,8" notitle
