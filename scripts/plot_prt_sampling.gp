# PRT report (marionette prt report), 2: transfer sampling error against the ray count N, n = 4,
# for a vertex that sees a cone of the given half-angle (90 degrees: unshadowed), with the
# least-squares fits of log error against log N.
# gnuplot -e "data='docs/data/prt'; img='docs/img'" scripts/plot_prt_sampling.gp
if (!exists("data")) data = "docs/data/prt"
if (!exists("img")) img = "docs/img"
file = data."/transfer_sampling.csv"
cases = system("tail -n +2 '".file."' | cut -d, -f1 | uniq | tr '\\n' ' '")
set datafile separator ","
set terminal pngcairo size 900,560 font "sans,11"
set output img."/prt_transfer_sampling.png"
set title "Stratified cosine-weighted transfer against the exact cone transfer (n = 4)" noenhanced
set xlabel "rays per vertex N"
set ylabel "mean relative L2 error of the transfer vector"
set logscale xy
set format x "10^{%L}"
set format y "10^{%L}"
set grid
set key top right
slope(c) = system("awk -F, -v c=".c." 'NR > 1 && $1 == c { print $6; exit }' '".file."'")
plot for [i = 1:words(cases)] file skip 1 using (strcol(1) eq word(cases, i) ? $2 : NaN):3 \
       with points pt 7 ps 1.1 lc i title sprintf("cone %s deg", word(cases, i)), \
     for [i = 1:words(cases)] file skip 1 using (strcol(1) eq word(cases, i) ? $2 : NaN):5 \
       with lines dt 2 lw 1.5 lc i title sprintf("fit, slope %s", slope(word(cases, i)))
