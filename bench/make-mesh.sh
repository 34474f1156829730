#!/usr/bin/env bash
# Writes a big triangle mesh and a scene showing it, for big-mesh benchmarks: a bumpy
# ball of about N triangles (a sphere displaced by a few waves, closed, its vertices
# shared; bench/make_mesh.cpp makes the triangles), on a plane under two lights, at
# 1920x1080. N = 1000000 gives exactly a million triangles.
#   bench/make-mesh.sh N DIR/NAME [--pov]
# writes DIR/NAME.ply (binary), DIR/NAME.obj, DIR/NAME.txt (the scene, its mesh naming
# NAME.ply) and DIR/NAME-obj.txt (the same naming NAME.obj); with --pov also the POV-Ray
# twin DIR/NAME.pov, whose object is a mesh2 of the same triangles (DIR/NAME.inc).
# The generator is $MAKE_MESH, else make_mesh beside build/bin/raytracer.
set -euo pipefail
[ $# -ge 2 ] || { echo "usage: $0 N DIR/NAME [--pov]" >&2; exit 2; }
n=$1 out=$2 pov=${3:-}
here=$(cd "$(dirname "$0")" && pwd)
gen=${MAKE_MESH:-$here/../build/bin/make_mesh}
[ -x "$gen" ] || { echo "make-mesh.sh: no generator at $gen (build the bench targets, or set MAKE_MESH)" >&2; exit 2; }
name=$(basename "$out")
mkdir -p "$(dirname "$out")"
if [ "$pov" = --pov ]; then "$gen" "$n" "$out.ply" --pov "$out.inc" >/dev/null; else "$gen" "$n" "$out.ply" >/dev/null; fi
"$gen" "$n" "$out.obj" >/dev/null
scene() {  # MODEL FILE
    cat > "$2" <<SCENE
// $name -- a bumpy ball of about $n triangles ($1, bench/make-mesh.sh) on a plane, 2 lights
thing {
  mesh {
    file "$1"
    position 0 0 1.2
    material { scattering 1 colour 0.85 0.55 0.35 }
  }
}
special_thing {
  plane { material { scattering 1 colour 0.6 0.6 0.6 } point 1 0 0 0  point 2 1 0 0  point 3 0 1 0  point 4 0 0 1 }
}
light {
  spotlight { colour 60 60 57 position -4 -6 8 }
  spotlight { colour 20 21 25 position 5 3 6 }
}
camera { position 0 -4.2 2.4 centre 0 0 1 up 0 0 2 projection 2 angle_x 60 angle_y 35.9834 }
picture_size { x_max 1920 y_max 1080 }
end
SCENE
}
scene "$name.ply" "$out.txt"
scene "$name.obj" "$out-obj.txt"
if [ "$pov" = --pov ]; then
    # POV-Ray's twin, with make-grid.sh's conventions: the same camera and light
    # fall-off (2 / (1 + (d / FD)^2) C / (2 FD^2) ~ C / d^2), no anti-aliasing.
    cat > "$out.pov" <<POV
// $name.pov -- POV-Ray 3.7 twin of $name.txt: the same triangles as a mesh2 ($name.inc)
#version 3.7;
global_settings { assumed_gamma 1.0 max_trace_level 20 adc_bailout 1/255 ambient_light rgb <0.25, 0.25, 0.25> }
background { rgb 0 }
#declare DEG = 3.14159/180;
camera { perspective location <0, -4.2, 2.4> direction <0, 0, 1> right -x*2*tan(60/2*DEG) up y*2*tan(35.9834/2*DEG) sky <0, 0, 1> look_at <0, 0, 1> }
#declare FD = 0.01;
light_source { <-4, -6, 8>, color rgb <60, 60, 57>/(2*FD*FD) fade_distance FD fade_power 2 }
light_source { <5, 3, 6>, color rgb <20, 21, 25>/(2*FD*FD) fade_distance FD fade_power 2 }
plane { <0, 0, 1>, 0 texture { pigment { color rgb <0.6, 0.6, 0.6> } finish { ambient 0.1 diffuse 0.9 } } }
#include "$name.inc"
object { Blob translate <0, 0, 1.2> texture { pigment { color rgb <0.85, 0.55, 0.35> } finish { ambient 0.1 diffuse 0.9 } } }
POV
fi
