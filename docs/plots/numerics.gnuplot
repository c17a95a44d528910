# Error of hit points against scale and distance, per primitive, float and double (docs/numerics.md).
# Reads docs/numerics/error_vs_scale.csv and docs/numerics/showcase_footprint.csv (ci/plot-numerics).
set terminal svg size 1300,1000 font "sans,11" background "white"
set output "docs/images/numerics_error_vs_scale.svg"
set datafile separator ","
set logscale xy
set format x "10^{%T}"
set format y "10^{%T}"
set grid
set multiplot layout 2,2 title "Hit points' distance from the true surface (largest over 24 × 24 primary rays), in units of the object's size"

subjects = "plane sphere cylinder box union intersection difference"
colour(i) = word("#1f77b4 #d62728 #2ca02c #9467bd #ff7f0e #8c564b #e377c2", i)
u_float = 2.0**-24
u_double = 2.0**-53
# Rows of one subject and tracer, in one sweep: $3 scale, $4 shift, $5 camera distance, $8 error.
rows_of(file, s, t, sweep) = sprintf("< awk -F, '$1==\"%s\" && $2==\"%s\" && %s' %s", s, t, sweep, file)
rows(s, t, sweep) = rows_of("docs/numerics/error_vs_scale.csv", s, t, sweep)
# The same table measured with the secondary-ray rule this replaced (64·ε·(|p| + t), no re-projection).
rows_before(s, t, sweep) = rows_of("docs/numerics/error_vs_scale_before.csv", s, t, sweep)
by_scale = "$4==0 && $5==1"
by_shift = "$3==1 && $5==1 && $4>0"

set key outside bottom center horizontal maxcols 4 font ",8"
set title "Uniform scale (object of size s at the origin)"
set xlabel "size s"
set ylabel "error / size"
set yrange [1e-17:1]
plot for [i=1:7] rows(word(subjects, i), "sse", by_scale) using 3:8 with linespoints lc rgb colour(i) pt 7 ps 0.5 title word(subjects, i)." sse (float)", \
     for [i=1:7] rows(word(subjects, i), "reference", by_scale) using 3:8 with linespoints lc rgb colour(i) dt 2 pt 6 ps 0.5 title word(subjects, i)." reference (double)", \
     16*u_float with lines lc rgb "black" lw 2 title "asserted: 16 u_{float}", \
     16*u_double with lines lc rgb "gray40" lw 2 title "asserted: 16 u_{double}"

set key inside top left font ",9"
set title "Distance from the origin (object of size 1 moved by d)"
set xlabel "distance d"
set xrange [5:2e6]
plot for [i=1:7] rows(word(subjects, i), "sse", by_shift) using 4:8 with linespoints lc rgb colour(i) pt 7 ps 0.5 notitle, \
     for [i=1:7] rows(word(subjects, i), "reference", by_shift) using 4:8 with linespoints lc rgb colour(i) dt 2 pt 6 ps 0.5 notitle, \
     16*u_float*(1+x) with lines lc rgb "black" lw 2 title "16 u_{float} (1 + d)", \
     16*u_double*(1+x) with lines lc rgb "gray40" lw 2 title "16 u_{double} (1 + d)"
unset xrange

set title "Camera far away (object of size 1 at the origin, eye k times farther)"
set xlabel "camera distance factor k"
by_camera = "$3==1 && $4==0"
set key inside center right font ",9"
plot for [i=1:7] rows(word(subjects, i), "sse", by_camera) using 5:8 with linespoints lc rgb colour(i) pt 7 ps 0.5 notitle, \
     for [i=1:7] rows(word(subjects, i), "reference", by_camera) using 5:8 with linespoints lc rgb colour(i) dt 2 pt 6 ps 0.5 notitle, \
     for [i=1:7] rows_before(word(subjects, i), "sse", by_camera) using 5:8 with linespoints lc rgb colour(i) dt 3 pt 4 ps 0.5 title (i == 1 ? "sse before the fix (each colour a subject)" : ""), \
     16*u_float with lines lc rgb "black" lw 2 title "16 u_{float}", \
     16*u_double with lines lc rgb "gray40" lw 2 title "16 u_{double}"

set key inside top left font ",9"
set title "Showcase moved away from the origin: error / pixel footprint (sse)"
set xlabel "distance d"
set ylabel "error / pixel footprint"
set yrange [1e-4:100]
primitives = "plane sphere cylinder box"
footprint(p) = sprintf("< awk -F, '$1==\"sse\" && $2==\"%s\"' docs/numerics/showcase_footprint.csv", p)
plot for [i=1:4] footprint(word(primitives, i)) using 3:4 with linespoints lc rgb colour(i) pt 7 ps 0.5 title word(primitives, i), \
     1 with lines lc rgb "black" lw 2 title "one pixel"
unset multiplot
