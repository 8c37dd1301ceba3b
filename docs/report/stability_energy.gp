set terminal pngcairo size 1100,2660 noenhanced font "sans,9"
set output "stability_energy.png.tmp"
set multiplot layout 7,2 title "Energy growth: max over steps of (E - E0)/E0 per case (up to the stop for stopped runs; dashed: 5 %)\ngreen: stable; orange: recovered by watchdog retries; red: lost particles or a drop broken up; red cross: stopped by the watchdog"
set logscale y
set yrange [0.0001:1000]
set grid ytics
set xtics rotate by 30 right
set ylabel "energy growth (log)"
set arrow from graph 0, first 0.05 to graph 1, first 0.05 nohead dt 2 lc rgb "#555555"
set title "wcsph: stiffness"
set xrange [-0.5:5.5]
set xtics ("k=10" 0, "k=100" 1, "k=400" 2, "k=1000" 3, "k=10000" 4, "k=100000" 5)
plot '-' using 1:2:3:4 with points pointtype variable ps 2 lw 3 lc rgb variable notitle
0 0.00425762 2 14034728
1 0.0320595 2 14034728
2 0.0362088 7 2924588
3 0.0371277 7 2924588
4 0.034264 7 2924588
5 0.0522574 7 2924588
e
set title "dfsph: density_tolerance"
set xrange [-0.5:5.5]
set xtics ("tol=0.05" 0, "tol=0.01" 1, "tol=0.001" 2, "tol=0.0005" 3, "tol=0.0001" 4, "tol=1e-05" 5)
plot '-' using 1:2:3:4 with points pointtype variable ps 2 lw 3 lc rgb variable notitle
0 0.0001 7 2924588
1 0.0001 7 2924588
2 0.0001 7 2924588
3 0.0001 7 2924588
4 0.0001 7 2924588
5 0.0001 7 2924588
e
set title "wcsph: density_ratio"
set xrange [-0.5:7.5]
set xtics ("1:1 mass" 0, "1:1 number" 1, "1:10 mass" 2, "1:10 number" 3, "1:100 mass" 4, "1:100 number" 5, "1:1000 mass" 6, "1:1000 number" 7)
plot '-' using 1:2:3:4 with points pointtype variable ps 2 lw 3 lc rgb variable notitle
0 0.000181642 7 2924588
1 0.000181642 7 2924588
2 0.0001 2 14034728
3 0.0001 7 2924588
4 0.0001 2 14034728
5 0.000120252 7 2924588
6 0.0001 2 14034728
7 0.000740096 7 2924588
e
set title "dfsph: density_ratio"
set xrange [-0.5:7.5]
set xtics ("1:1 mass" 0, "1:1 number" 1, "1:10 mass" 2, "1:10 number" 3, "1:100 mass" 4, "1:100 number" 5, "1:1000 mass" 6, "1:1000 number" 7)
plot '-' using 1:2:3:4 with points pointtype variable ps 2 lw 3 lc rgb variable notitle
0 0.00375911 7 2924588
1 0.00375911 7 2924588
2 0.0001 2 14034728
3 0.00575256 7 2924588
4 0.0001 2 14034728
5 0.00642129 7 2924588
6 0.0001 2 14034728
7 0.00650021 7 2924588
e
set title "wcsph: viscosity"
set xrange [-0.5:6.5]
set xtics ("mu=0" 0, "mu=0.01" 1, "mu=0.1" 2, "mu=1" 3, "mu=10" 4, "mu=100" 5, "mu=1000" 6)
plot '-' using 1:2:3:4 with points pointtype variable ps 2 lw 3 lc rgb variable notitle
0 0.0372038 7 2924588
1 0.0371961 7 2924588
2 0.0371277 7 2924588
3 0.03645 7 2924588
4 0.0308598 7 2924588
5 0.0270401 7 2924588
6 0.219909 7 2924588
e
set title "dfsph: viscosity"
set xrange [-0.5:6.5]
set xtics ("mu=0" 0, "mu=0.01" 1, "mu=0.1" 2, "mu=1" 3, "mu=10" 4, "mu=100" 5, "mu=1000" 6)
plot '-' using 1:2:3:4 with points pointtype variable ps 2 lw 3 lc rgb variable notitle
0 0.0001 7 2924588
1 0.0001 7 2924588
2 0.0001 7 2924588
3 0.0001 7 2924588
4 0.0001 7 2924588
5 0.0001 7 2924588
6 0.0001 7 2924588
e
set title "wcsph: dt_factor"
set xrange [-0.5:6.5]
set xtics ("f=0.5" 0, "f=1" 1, "f=2" 2, "f=5" 3, "f=10" 4, "f=25" 5, "f=25 no retries" 6)
plot '-' using 1:2:3:4 with points pointtype variable ps 2 lw 3 lc rgb variable notitle
0 0.0202051 7 2924588
1 0.0371277 7 2924588
2 0.228688 7 2924588
3 4.26835 2 14034728
4 7.98634 2 14034728
5 5.92564 2 14034728
6 0.0001 2 14034728
e
set title "dfsph: dt_factor"
set xrange [-0.5:6.5]
set xtics ("f=0.5" 0, "f=1" 1, "f=2" 2, "f=5" 3, "f=10" 4, "f=25" 5, "f=25 no retries" 6)
plot '-' using 1:2:3:4 with points pointtype variable ps 2 lw 3 lc rgb variable notitle
0 0.0001 7 2924588
1 0.0001 7 2924588
2 0.0001 7 16744206
3 0.0001 7 16744206
4 0.0001 7 16744206
5 0.0001 7 16744206
6 0.0001 2 14034728
e
set title "wcsph: temperature"
set xrange [-0.5:4.5]
set xtics ("dT=0" 0, "dT=10" 1, "dT=100" 2, "dT=1000" 3, "dT=5000" 4)
plot '-' using 1:2:3:4 with points pointtype variable ps 2 lw 3 lc rgb variable notitle
0 0.000181642 7 2924588
1 0.000313472 7 2924588
2 0.0101268 7 2924588
3 0.154314 7 2924588
4 2.55861 2 14034728
e
set title "dfsph: temperature"
set xrange [-0.5:4.5]
set xtics ("dT=0" 0, "dT=10" 1, "dT=100" 2, "dT=1000" 3, "dT=5000" 4)
plot '-' using 1:2:3:4 with points pointtype variable ps 2 lw 3 lc rgb variable notitle
0 0.00375911 7 2924588
1 0.00419315 7 2924588
2 0.0184937 7 2924588
3 0.15705 7 2924588
4 1000 2 14034728
e
set title "wcsph: spacing"
set xrange [-0.5:5.5]
set xtics ("s=0.05m" 0, "s=0.025m" 1, "s=0.01m" 2, "s=0.005m" 3, "s=0.0001m (scene x0.01)" 4, "s=1m (scene x100)" 5)
plot '-' using 1:2:3:4 with points pointtype variable ps 2 lw 3 lc rgb variable notitle
0 0.377786 7 2924588
1 0.875479 7 2924588
2 0.0371277 7 2924588
3 0.0208351 7 2924588
4 0.0198542 7 2924588
5 0.000774388 2 14034728
e
set title "dfsph: spacing"
set xrange [-0.5:5.5]
set xtics ("s=0.05m" 0, "s=0.025m" 1, "s=0.01m" 2, "s=0.005m" 3, "s=0.0001m (scene x0.01)" 4, "s=1m (scene x100)" 5)
plot '-' using 1:2:3:4 with points pointtype variable ps 2 lw 3 lc rgb variable notitle
0 0.0001 7 2924588
1 0.000596913 7 2924588
2 0.0001 7 2924588
3 0.0001 7 16744206
4 0.0001 7 2924588
5 0.00257572 7 2924588
e
set title "wcsph: surface_tension"
set xrange [-0.5:7.5]
set xtics ("sigma=0.0728" 0, "sigma=1" 1, "sigma=10" 2, "sigma=100" 3, "sigma=1000" 4, "sigma=1 s=5mm" 5, "sigma=3 s=5mm" 6, "sigma=10 s=5mm" 7)
plot '-' using 1:2:3:4 with points pointtype variable ps 2 lw 3 lc rgb variable notitle
0 0.0001 7 2924588
1 0.0001 7 2924588
2 0.0001 7 2924588
3 0.0001 7 14034728
4 0.0001 2 14034728
5 0.0001 7 2924588
6 0.0001 7 2924588
7 0.0001 7 14034728
e
set title "dfsph: surface_tension"
set xrange [-0.5:7.5]
set xtics ("sigma=0.0728" 0, "sigma=1" 1, "sigma=10" 2, "sigma=100" 3, "sigma=1000" 4, "sigma=1 s=5mm" 5, "sigma=3 s=5mm" 6, "sigma=10 s=5mm" 7)
plot '-' using 1:2:3:4 with points pointtype variable ps 2 lw 3 lc rgb variable notitle
0 0.0001 7 2924588
1 0.0001 7 2924588
2 0.0001 7 2924588
3 0.0001 7 2924588
4 0.0001 7 2924588
5 0.0001 7 2924588
6 0.0001 7 14034728
7 0.0001 7 14034728
e
unset multiplot
