# Speed-up against error, one point per configuration (the Pareto front), and time per ray against
# scene size, from the CSV files of `twinray bench --csv FILE --scaling`. Run by ci/plot-trade:
#   gnuplot -e "summary='bench-summary.csv'; scaling='bench-scaling.csv'; peers='bench-scaling-peers.csv'; outdir='docs/images'" docs/plots/trade.gnuplot
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

# Time per ray against the primitive count, one panel per family, from bench-scaling.csv (renders: every ray)
# and bench-scaling-peers.csv (first hits of primary rays, Embree on its widest kernels, on SSE4.2 and as coherent
# packets on both; POV-Ray's trace, from its statistics, over our rays). Cells left out ("—") are not numbers and are skipped.
set output outdir."/scaling.png"
set terminal pngcairo size 2200,560 font "DejaVu Sans,10"
set multiplot layout 1,5 title "twinray bench --scaling: time per ray against primitives (one thread, CPU time; log-log)"
set logscale xy
set format x "10^{%L}"
set format y "10^{%L}"
set xlabel "primitives"
set ylabel "ns per ray"
set xrange [5:2e6]
set yrange [3:3e7]
set key top left font ",8"
in_family(family, value) = strcol(1) eq family ? value : NaN
do for [family in "spheres fractal lattice sphere-mesh tetra"] {
    set title family
    plot scaling using 2:(in_family(family, column(3))) with linespoints lw 2 pt 7 lc rgb "#1f77b4" title "sse bvh", \
         scaling using 2:(in_family(family, column(4))) with linespoints lw 2 pt 6 dt 2 lc rgb "#1f77b4" title "sse brute force", \
         scaling using 2:(in_family(family, column(5))) with linespoints lw 2 pt 5 lc rgb "#d62728" title "ref<double> bvh", \
         scaling using 2:(in_family(family, column(6))) with linespoints lw 2 pt 4 dt 2 lc rgb "#d62728" title "ref<double> brute force", \
         peers using 2:(in_family(family, column(4))) with linespoints lw 2 pt 9 lc rgb "#2ca02c" title "sse first hit", \
         peers using 2:(in_family(family, column(5))) with linespoints lw 2 pt 8 lc rgb "#ff7f0e" title "embree rtcIntersect1 first hit", \
         peers using 2:(in_family(family, column(7))) with linespoints lw 2 pt 8 dt 2 lc rgb "#ff7f0e" title "embree SSE4.2 first hit", \
         peers using 2:(in_family(family, column(13))) with linespoints lw 2 pt 8 dt 3 lc rgb "#8c564b" title "embree coherent packets first hit", \
         peers using 2:(in_family(family, column(16))) with linespoints lw 2 pt 8 dt 4 lc rgb "#8c564b" title "embree SSE4.2 coherent packets first hit", \
         peers using 2:(in_family(family, column(25))) with linespoints lw 2 pt 3 lc rgb "#9467bd" title "povray +WT1 trace, per our ray"
}
unset multiplot
