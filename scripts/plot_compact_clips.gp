# Size against error of compact clips (docs/accuracy.md), with ozz-animation's points.
#   gnuplot scripts/plot_compact_clips.gp   (from the repository root)
# Data: docs/data/compact_clip_budget.csv (CompactClipAccuracy.SizeFallsAsTheBudgetGrows's CSV)
#       docs/data/ozz_clip_size_error.csv (scripts/compare-ozz, out of tree)
set terminal pngcairo size 900,560 font ",11"
set output "docs/compact_clip_size_error.png"
set datafile separator ","
set logscale xy
set xlabel "bytes of keys (three clips, with in-place root copies for Marionette)"
set ylabel "max error at virtual vertices 3 cm from each joint (mm)"
set title "Compact clips: size against error (budgets 0.03, 0.1, 0.3, 1, 2 mm)"
set key top right
set grid
set xrange [8000:400000]
set yrange [0.005:300]
plot "docs/data/compact_clip_budget.csv" using (strcol(1) eq "RobotExpressive" ? $3 : 1/0):($5*1000) every ::1 with linespoints pt 7 lw 2 title "Marionette, RobotExpressive", \
     "docs/data/compact_clip_budget.csv" using (strcol(1) eq "Pab" ? $3 : 1/0):($5*1000) every ::1 with linespoints pt 5 lw 2 title "Marionette, Pab (own skeletons)", \
     "docs/data/compact_clip_budget.csv" using (strcol(1) eq "Pab bound" ? $3 : 1/0):($5*1000) every ::1 with linespoints pt 9 lw 2 title "Marionette, Pab bound to pab\\_arnaud (as ozz plays it)", \
     "docs/data/ozz_clip_size_error.csv" using (strcol(1) eq "RobotExpressive" ? $3 : 1/0):($4*1000) every ::1 with points pt 6 ps 1.6 title "ozz 0.16, RobotExpressive (no opt., defaults, defaults/100)", \
     "docs/data/ozz_clip_size_error.csv" using (strcol(1) eq "Pab" ? $3 : 1/0):($4*1000) every ::1 with points pt 4 ps 1.6 title "ozz 0.16, Pab (bound)", \
     0.1 with lines dt 2 lc rgb "gray" title "0.1 mm (default budget)"
