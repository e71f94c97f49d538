# PRT report (marionette prt report), 1: SH lighting truncation, mean relative irradiance error
# against the band count n, one line per light probe.
# gnuplot -e "data='docs/data/prt'; img='docs/img'" scripts/plot_prt_lighting.gp
if (!exists("data")) data = "docs/data/prt"
if (!exists("img")) img = "docs/img"
file = data."/lighting_truncation.csv"
maps = system("tail -n +2 '".file."' | cut -d, -f1 | uniq | tr '\\n' ' '")
set datafile separator ","
set terminal pngcairo size 900,560 font "sans,11"
set output img."/prt_lighting_truncation.png"
set title "SH irradiance against brute force: mean relative error over the normals" noenhanced
set xlabel "bands n (n^2 coefficients per channel)"
set ylabel "mean relative irradiance error"
set logscale y
set format y "10^{%L}"
set xrange [1.8:8.2]
set xtics 1
set grid
set key outside right noenhanced font "sans,9"
# 8 colours, then the same colours dashed with other points
plot for [i = 1:words(maps)] file skip 1 using (strcol(1) eq word(maps, i) ? $2 : NaN):4 \
       with linespoints lw 2 lc i dt 1 + (i > 8) pt 7 - 3 * (i > 8) ps 0.8 title word(maps, i)
