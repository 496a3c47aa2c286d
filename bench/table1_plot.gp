# Table 1's sweep plot: ns per particle-step against triangle count (bench/run.sh runs it on the data
# bench/report.py writes). gnuplot -e "data='SWEEP.dat'; out='docs/images/table1_sweep.png'" bench/table1_plot.gp
set terminal pngcairo size 820,620 font ",11"
set output out
set title "Table 1 sweep: cost per particle-step against triangle count (one thread)"
set xlabel "triangles"
set ylabel "ns per particle-step (median)"
set logscale x
set logscale y
set format x "%.0s%c"
set grid xtics ytics mxtics
set key below maxrows 3 width -4
set xrange [3000:2000000]
set yrange [1:*]
plot data using 2:6 with linespoints lw 2 pt 7 title "Embree, best packet variant", \
     data using 2:7 with linespoints lw 2 pt 5 title "NanoVDB nearest + central differences", \
     data using 2:8 with linespoints lw 2 pt 4 title "NanoVDB trilinear + gradient", \
     data using 2:5 with linespoints lw 2 pt 9 title "dngrid bricked, impact+drag+flow", \
     data using 2:9 with linespoints lw 2 pt 13 title "dngrid bricked exact, impact+drag+flow", \
     data using 2:4 with linespoints lw 2 pt 8 title "dngrid bricked, impact", \
     data using 2:3 with linespoints lw 1 dt 2 pt 1 title "no collision"
