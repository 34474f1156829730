#!/usr/bin/env bash
# Writes an N x N grid of spheres: spheres-10k's layout (radius 0.4, spacing 1, diffuse
# and 50 % mirror spheres alternating, a plane, two lights) scaled up, for big-scene
# tests. N = 1000 gives a million spheres in a ~114 MB file. With a third argument it
# also writes the POV-Ray twin.
#   bench/make-grid.sh N OUT.txt [OUT.pov]
set -euo pipefail
[ $# -ge 2 ] || { echo "usage: $0 N OUT.txt [OUT.pov]" >&2; exit 2; }
n=$1 txt=$2 pov=${3:-}
awk -v n="$n" -v out="$txt" -v pov="$pov" 'function f(x) { s = sprintf("%.6f", x); sub(/0+$/, "", s); sub(/\.$/, "", s); if (s == "-0") s = "0"; return s }
BEGIN {
    k = n / 100.0                      # scale of camera and lights against spheres-10k
    half = (n - 1) / 2
    print "// " n "x" n " grid of spheres (radius 0.4, spacing 1), diffuse and 50% mirror alternating" > out
    print "thing {" > out
    if (pov != "") {
        print "#version 3.7;" > pov
        print "global_settings { assumed_gamma 1.0 max_trace_level 20 adc_bailout 1/255 ambient_light rgb <1.167236, 1.191851, 1.225797> }" > pov
        print "background { rgb 0 }" > pov
        print "#declare DEG = 3.14159/180;" > pov
        print "camera { perspective location <0, " f(-110*k) ", " f(70*k) "> direction <0, 0, 1> right -x*2*tan(60/2*DEG) up y*2*tan(35.9834/2*DEG) sky <0, 0, 1> look_at <0, " f(-15*k) ", 0> }" > pov
        print "#declare FD = 0.01;" > pov
        print "light_source { <" f(-40*k) ", " f(-60*k) ", " f(80*k) ">, color rgb <" f(8000*k*k) ", " f(8000*k*k) ", " f(7600*k*k) ">/(2*FD*FD) fade_distance FD fade_power 2 }" > pov
        print "light_source { <" f(50*k) ", " f(30*k) ", " f(60*k) ">, color rgb <" f(3000*k*k) ", " f(3200*k*k) ", " f(3800*k*k) ">/(2*FD*FD) fade_distance FD fade_power 2 }" > pov
        print "#declare T_Mirror = texture { pigment { color rgb <0.9, 0.9, 0.9> } finish { ambient 0.05 diffuse 0.45 reflection 0.5 } }" > pov
        print "plane { <0, 0, 1>, 0 texture { pigment { color rgb <0.6, 0.6, 0.6> } finish { ambient 0.1 diffuse 0.9 } } }" > pov
    }
    for (j = 0; j < n; ++j) for (i = 0; i < n; ++i) {
        x = f(i - half); y = f(j - half)
        if ((i + j) % 2 == 0) {
            c = f(0.25 + 0.75 * i / (n - 1)) " " f(0.25 + 0.75 * j / (n - 1)) " 0.55"
            printf "\tsphere {\n\t\tmaterial { scattering 1 colour %s }\n\t\tposition %s %s 0.4\n\t\tradius 0.4\n\t}\n", c, x, y > out
            if (pov != "") { gsub(/ /, ", ", c); printf "sphere { <%s, %s, 0.4>, 0.4 texture { pigment { color rgb <%s> } finish { ambient 0.1 diffuse 0.9 } } }\n", x, y, c > pov }
        } else {
            printf "\tsphere {\n\t\tmaterial { reflection 0.5 scattering 0.5 colour 0.9 0.9 0.9 }\n\t\tposition %s %s 0.4\n\t\tradius 0.4\n\t}\n", x, y > out
            if (pov != "") printf "sphere { <%s, %s, 0.4>, 0.4 texture { T_Mirror } }\n", x, y > pov
        }
    }
    print "}\n" > out
    print "special_thing {\n\tplane {\n\t\tmaterial { scattering 1 colour 0.6 0.6 0.6 }\n\t\tpoint 1 0 0 0\n\t\tpoint 2 1 0 0\n\t\tpoint 3 0 1 0\n\t\tpoint 4 0 " f(-110*k) " " f(70*k) "\n\t}\n}\n" > out
    print "light {\n\tspotlight {\n\t\tcolour " f(8000*k*k) " " f(8000*k*k) " " f(7600*k*k) "\n\t\tposition " f(-40*k) " " f(-60*k) " " f(80*k) "\n\t}" > out
    print "\tspotlight {\n\t\tcolour " f(3000*k*k) " " f(3200*k*k) " " f(3800*k*k) "\n\t\tposition " f(50*k) " " f(30*k) " " f(60*k) "\n\t}\n}\n" > out
    print "camera {\n\tposition 0 " f(-110*k) " " f(70*k) "\n\tcentre 0 " f(-15*k) " 0\n\tup 0 " f(-15*k) " 1\n\tprojection 2\n\tangle_x 60\n\tangle_y 35.9834\n}\n" > out
    print "picture_size {\n\tx_max 1920\n\ty_max 1080\n}\n\nend" > out
}'
