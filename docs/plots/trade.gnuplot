# Speed-up against error, one point per configuration (the Pareto front), and time per ray against
# scene size, from the CSV files of `twinray bench --csv FILE --scaling`. Run by ci/plot-trade:
#   gnuplot -e "summary='bench-summary.csv'; scaling='bench-scaling.csv'; outdir='docs/images'" docs/plots/trade.gnuplot
set datafile separator ","
set terminal pngcairo size 1200,520 font "DejaVu Sans,10"
floor = 1e-8   # an error of exactly 0 (reference<double> against itself) is drawn on this line

set output outdir."/trade.png"
set multiplot layout 1,2 title "twinray: speed-up over reference<double> (geometric mean over scenes) against the worst scene's error"
set logscale x
set format x "1e%L"
set grid
set key off
set ylabel "speed-up over reference<double> (one thread unless marked nT)"
set xlabel "primary-ray t relative error, max (worst scene; 0 drawn at 1e-8)"
plot summary using (($9) > floor ? $9 : floor):2 every ::1 with points pt 7 ps 1.2, \
     summary using (($9) > floor ? $9 : floor):2:1 every ::1 with labels offset 1,0.6 left rotate by 20 font ",8"
set xlabel "normal angle error, max, degrees (worst scene; 0 drawn at 1e-8)"
plot summary using (($10) > floor ? $10 : floor):2 every ::1 with points pt 7 ps 1.2, \
     summary using (($10) > floor ? $10 : floor):2:1 every ::1 with labels offset 1,0.6 left rotate by 20 font ",8"
unset multiplot

set output outdir."/scaling.png"
set terminal pngcairo size 800,560 font "DejaVu Sans,10"
set title "Time per ray against the number of spheres (generated sphere fields; no acceleration structure)"
set logscale xy
set xlabel "spheres"
set ylabel "ns per ray"
set key top left
set xrange [7:14000]
stats scaling using 1 nooutput
columns = STATS_columns
plot for [column=3:columns] scaling using 1:column with linespoints lw 2 title columnhead(column)
