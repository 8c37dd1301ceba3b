set terminal pngcairo size 1100,2660 noenhanced font "sans,9"
set output "stability.png.tmp"
set multiplot layout 7,2 title "Largest compression (rho - rho0)/rho0 of accepted steps per case (stopped runs drawn at the watchdog's limit 0.5)\ngreen: stable; orange: recovered by watchdog retries; red: lost particles or a drop broken up; red cross: stopped by the watchdog"
set logscale y
set yrange [0.0001:2]
set grid ytics
set xtics rotate by 30 right
set ylabel "max density error"
set title "wcsph: stiffness"
set xrange [-0.5:5.5]
set xtics ("k=10" 0, "k=100" 1, "k=400" 2, "k=1000" 3, "k=10000" 4, "k=100000" 5)
plot '-' using 1:2:3:4 with points pointtype variable ps 2 lw 3 lc rgb variable notitle
0 0.5 2 14034728
1 0.5 2 14034728
2 0.489089 7 2924588
3 0.255495 7 2924588
4 0.0916705 7 2924588
5 0.0378139 7 2924588
e
set title "dfsph: density_tolerance"
set xrange [-0.5:5.5]
set xtics ("tol=0.05" 0, "tol=0.01" 1, "tol=0.001" 2, "tol=0.0005" 3, "tol=0.0001" 4, "tol=1e-05" 5)
plot '-' using 1:2:3:4 with points pointtype variable ps 2 lw 3 lc rgb variable notitle
0 0.00948104 7 2924588
1 0.00948104 7 2924588
2 0.00813153 7 2924588
3 0.00842073 7 2924588
4 0.0096295 7 2924588
5 0.00927435 7 2924588
e
set title "wcsph: density_ratio"
set xrange [-0.5:7.5]
set xtics ("1:1 mass" 0, "1:1 number" 1, "1:10 mass" 2, "1:10 number" 3, "1:100 mass" 4, "1:100 number" 5, "1:1000 mass" 6, "1:1000 number" 7)
plot '-' using 1:2:3:4 with points pointtype variable ps 2 lw 3 lc rgb variable notitle
0 0.00783153 7 2924588
1 0.00783153 7 2924588
2 0.5 2 14034728
3 0.00653863 7 2924588
4 0.5 2 14034728
5 0.0232911 7 2924588
6 0.5 2 14034728
7 0.0618782 7 2924588
e
set title "dfsph: density_ratio"
set xrange [-0.5:7.5]
set xtics ("1:1 mass" 0, "1:1 number" 1, "1:10 mass" 2, "1:10 number" 3, "1:100 mass" 4, "1:100 number" 5, "1:1000 mass" 6, "1:1000 number" 7)
plot '-' using 1:2:3:4 with points pointtype variable ps 2 lw 3 lc rgb variable notitle
0 0.007327 7 2924588
1 0.00545481 7 2924588
2 0.5 2 14034728
3 0.0038078 7 2924588
4 0.5 2 14034728
5 0.00512046 7 2924588
6 0.5 2 14034728
7 0.00849046 7 2924588
e
set title "wcsph: viscosity"
set xrange [-0.5:6.5]
set xtics ("mu=0" 0, "mu=0.01" 1, "mu=0.1" 2, "mu=1" 3, "mu=10" 4, "mu=100" 5, "mu=1000" 6)
plot '-' using 1:2:3:4 with points pointtype variable ps 2 lw 3 lc rgb variable notitle
0 0.25554 7 2924588
1 0.255535 7 2924588
2 0.255495 7 2924588
3 0.255095 7 2924588
4 0.251438 7 2924588
5 0.234052 7 2924588
6 0.19386 7 2924588
e
set title "dfsph: viscosity"
set xrange [-0.5:6.5]
set xtics ("mu=0" 0, "mu=0.01" 1, "mu=0.1" 2, "mu=1" 3, "mu=10" 4, "mu=100" 5, "mu=1000" 6)
plot '-' using 1:2:3:4 with points pointtype variable ps 2 lw 3 lc rgb variable notitle
0 0.00834998 7 2924588
1 0.00834167 7 2924588
2 0.00842073 7 2924588
3 0.009542 7 2924588
4 0.00855627 7 2924588
5 0.00966159 7 2924588
6 0.00959651 7 2924588
e
set title "wcsph: dt_factor"
set xrange [-0.5:6.5]
set xtics ("f=0.5" 0, "f=1" 1, "f=2" 2, "f=5" 3, "f=10" 4, "f=25" 5, "f=25 no retries" 6)
plot '-' using 1:2:3:4 with points pointtype variable ps 2 lw 3 lc rgb variable notitle
0 0.256146 7 2924588
1 0.255495 7 2924588
2 0.265243 7 2924588
3 0.5 2 14034728
4 0.5 2 14034728
5 0.5 2 14034728
6 0.5 2 14034728
e
set title "dfsph: dt_factor"
set xrange [-0.5:6.5]
set xtics ("f=0.5" 0, "f=1" 1, "f=2" 2, "f=5" 3, "f=10" 4, "f=25" 5, "f=25 no retries" 6)
plot '-' using 1:2:3:4 with points pointtype variable ps 2 lw 3 lc rgb variable notitle
0 0.00978553 7 2924588
1 0.0207997 7 2924588
2 0.269264 7 16744206
3 0.00986758 7 16744206
4 0.0623052 7 16744206
5 0.0623052 7 16744206
6 0.5 2 14034728
e
set title "wcsph: temperature"
set xrange [-0.5:4.5]
set xtics ("dT=0" 0, "dT=10" 1, "dT=100" 2, "dT=1000" 3, "dT=5000" 4)
plot '-' using 1:2:3:4 with points pointtype variable ps 2 lw 3 lc rgb variable notitle
0 0.00783153 7 2924588
1 0.00783572 7 2924588
2 0.00814277 7 2924588
3 0.0118068 7 2924588
4 0.5 2 14034728
e
set title "dfsph: temperature"
set xrange [-0.5:4.5]
set xtics ("dT=0" 0, "dT=10" 1, "dT=100" 2, "dT=1000" 3, "dT=5000" 4)
plot '-' using 1:2:3:4 with points pointtype variable ps 2 lw 3 lc rgb variable notitle
0 0.00513299 7 2924588
1 0.00856056 7 2924588
2 0.00774408 7 2924588
3 0.00969063 7 2924588
4 0.5 2 14034728
e
set title "wcsph: spacing"
set xrange [-0.5:5.5]
set xtics ("s=0.05m" 0, "s=0.025m" 1, "s=0.01m" 2, "s=0.005m" 3, "s=0.0001m (scene x0.01)" 4, "s=1m (scene x100)" 5)
plot '-' using 1:2:3:4 with points pointtype variable ps 2 lw 3 lc rgb variable notitle
0 0.110273 7 2924588
1 0.195722 7 2924588
2 0.255495 7 2924588
3 0.312323 7 2924588
4 0.0211384 7 2924588
5 0.5 2 14034728
e
set title "dfsph: spacing"
set xrange [-0.5:5.5]
set xtics ("s=0.05m" 0, "s=0.025m" 1, "s=0.01m" 2, "s=0.005m" 3, "s=0.0001m (scene x0.01)" 4, "s=1m (scene x100)" 5)
plot '-' using 1:2:3:4 with points pointtype variable ps 2 lw 3 lc rgb variable notitle
0 0.00421137 7 2924588
1 0.00591712 7 2924588
2 0.00842073 7 2924588
3 0.138592 7 16744206
4 0.0149884 7 2924588
5 0.00998135 7 2924588
e
set title "wcsph: surface_tension"
set xrange [-0.5:7.5]
set xtics ("sigma=0.0728" 0, "sigma=1" 1, "sigma=10" 2, "sigma=100" 3, "sigma=1000" 4, "sigma=1 s=5mm" 5, "sigma=3 s=5mm" 6, "sigma=10 s=5mm" 7)
plot '-' using 1:2:3:4 with points pointtype variable ps 2 lw 3 lc rgb variable notitle
0 0.00196152 7 2924588
1 0.0173305 7 2924588
2 0.0713251 7 2924588
3 0.274026 7 14034728
4 0.5 2 14034728
5 0.0329333 7 2924588
6 0.0703043 7 2924588
7 0.168872 7 14034728
e
set title "dfsph: surface_tension"
set xrange [-0.5:7.5]
set xtics ("sigma=0.0728" 0, "sigma=1" 1, "sigma=10" 2, "sigma=100" 3, "sigma=1000" 4, "sigma=1 s=5mm" 5, "sigma=3 s=5mm" 6, "sigma=10 s=5mm" 7)
plot '-' using 1:2:3:4 with points pointtype variable ps 2 lw 3 lc rgb variable notitle
0 0.000133994 7 2924588
1 0.0011517 7 2924588
2 0.00863234 7 2924588
3 0.00997983 7 2924588
4 0.00999844 7 2924588
5 0.00926697 7 2924588
6 0.00992586 7 14034728
7 0.00996247 7 14034728
e
unset multiplot
