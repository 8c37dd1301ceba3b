set terminal pngcairo size 1000,650 noenhanced font "sans,10"
set output "accuracy_layered.png.tmp"
$wcsph << EOD
7.53012 0.00555556 "10mm f=1 mass"
7.69237 0.0240741 "10mm f=1 number"
30.9552 0.00823045 "6.67mm f=1 mass"
31.5002 0.048011 "6.67mm f=1 number"
41.6026 0.018287 "5mm f=2 mass"
41.6354 0.0510417 "5mm f=2 number"
89.0155 0.0185185 "5mm f=1 mass"
96.6054 0.0685185 "5mm f=1 number"
EOD
$wcsphfront << EOD
7.53012 0.00555556 "10mm f=1 mass"
EOD
$dfsph << EOD
4.50162 0.35463 "10mm f=1 number"
5.11843 0.0203704 "10mm f=1 mass"
13.1164 0.950069 "6.67mm f=1 number"
19.3012 0.0142661 "6.67mm f=1 mass"
27.6345 0.956713 "5mm f=1 number"
34.9039 0.95787 "5mm f=2 number"
45.8429 0.0164352 "5mm f=1 mass"
49.5858 0.0275463 "5mm f=2 mass"
EOD
$dfsphfront << EOD
4.50162 0.35463 "10mm f=1 number"
5.11843 0.0203704 "10mm f=1 mass"
19.3012 0.0142661 "6.67mm f=1 mass"
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
