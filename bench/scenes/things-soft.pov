// things-soft.pov -- POV-Ray 3.7 twin of things-soft.txt: things-like.pov with area lights
// (5x5, adaptive 1, jitter, circular, orient: discs of the sphere lights' diameter facing
// each point) and focal blur (20 samples), rendered with anti-aliasing:
//   povray -D +A0.3 +W1280 +H720 +WT2 File_Gamma=1.0 +Ithings-soft.pov +Othings-soft.png
// A converged reference: Declare=AREA_N=17 Declare=AREA_ADAPT=3 Declare=BLUR_N=255 (bench/run.sh -R).
#version 3.7;
global_settings {
  assumed_gamma 1.0
  max_trace_level 20   // = raytracer2 depth limit
  adc_bailout 1/255      // POV default, stated explicitly
  ambient_light rgb <0.941532, 0.927589, 0.948495>   // sum C/r^2 of the lights at a reference point
}
background { rgb 0 }
#ifndef (AREA_N) #declare AREA_N = 5; #end
#ifndef (AREA_ADAPT) #declare AREA_ADAPT = 1; #end
#ifndef (BLUR_N) #declare BLUR_N = 20; #end
#declare DEG = 3.14159/180;   // raytracer2 degree factor
camera {
  perspective
  location <-9.8, -2.6, 6.3>
  direction <0, 0, 1>
  right -x*2*tan(60/2*DEG)   // full horizontal FOV angle_x; minus = right-handed
  up y*2*tan(35.9834/2*DEG)       // full vertical FOV angle_y
  sky <0, 0, 1>   // raytracer2 up point minus centre
  look_at <0.7, -0.2, 0.8>
  aperture 0.25   // the lens's diameter, as raytracer2's aperture
  blur_samples BLUR_N
  focal_point <0.7, -0.2, 0.8>
}
#declare FD = 0.01;   // light: 2/(1+(d/FD)^2) * C/(2 FD^2) ~= C/d^2
light_source { <-6, -7, 9>, color rgb <70, 70, 70>/(2*FD*FD) area_light <1.2, 0, 0>, <0, 1.2, 0>, AREA_N, AREA_N adaptive AREA_ADAPT jitter circular orient fade_distance FD fade_power 2 }
light_source { <5, -9, 6>, color rgb <40, 34, 28>/(2*FD*FD) area_light <1.2, 0, 0>, <0, 1.2, 0>, AREA_N, AREA_N adaptive AREA_ADAPT jitter circular orient fade_distance FD fade_power 2 }
light_source { <-1, 9, 10>, color rgb <30, 36, 48>/(2*FD*FD) area_light <1.2, 0, 0>, <0, 1.2, 0>, AREA_N, AREA_N adaptive AREA_ADAPT jitter circular orient fade_distance FD fade_power 2 }
plane { <0, 0, 1>, 0 texture { pigment { color rgb <0.9, 0.9, 0.85> } finish { ambient 0.075 diffuse 0.675 reflection 0.25 } } }
sphere { <-1.6, -1.2, 1>, 1 texture { pigment { color rgbt <1, 1, 1, 0.9> } finish { ambient 0 diffuse 0 reflection 0.1 } } interior_texture { pigment { color rgbt <1, 1, 1, 1> } finish { ambient 0 diffuse 0 reflection 0 } } interior { ior 1.5 } no_shadow }
sphere { <1.5, -3, 0.8>, 0.8 texture { pigment { color rgb <1, 0.2, 0.15> } finish { ambient 0.1 diffuse 0.9 } } }
sphere { <1.2, 1.4, 1.3>, 1.3 texture { pigment { color rgb <0.8, 0.85, 1> } finish { ambient 0.04 diffuse 0.36 reflection 0.6 } } }
sphere { <3.8, -0.8, 0.7>, 0.7 texture { pigment { color rgb <0.2, 1, 0.3> } finish { ambient 0.07 diffuse 0.63 reflection 0.3 } } }
sphere { <-2.8, 2.2, 0.5>, 0.5 texture { pigment { color rgb <1, 0.9, 0.1> } finish { ambient 0.1 diffuse 0.9 } } }
mesh { triangle { <2.4, -5.6, 0>, <4.6, -4.6, 0>, <2.7, -3.6, 0> } triangle { <2.4, -5.6, 0>, <4.6, -4.6, 0>, <3.1, -4.6, 2.3> } triangle { <2.4, -5.6, 0>, <2.7, -3.6, 0>, <3.1, -4.6, 2.3> } triangle { <4.6, -4.6, 0>, <2.7, -3.6, 0>, <3.1, -4.6, 2.3> } inside_vector <0, 0, 1> texture { pigment { color rgb <0.3, 0.5, 1> } finish { ambient 0.07 diffuse 0.63 reflection 0.3 } } }
cylinder { <3.2, 3.4, 0.5>, <5, 1.6, 2.6>, 0.5 texture { pigment { color rgb <1, 0.55, 0.1> } finish { ambient 0.1 diffuse 0.9 } } }
difference { sphere { <-0.9, 4.2, 1.1>, 1.1 } cylinder { <-2.6, 3.9, 1.3>, <0.8, 4.5, 0.9>, 0.45 } texture { pigment { color rgb <0.9, 0.9, 0.9> } finish { ambient 0.06 diffuse 0.54 reflection 0.4 } } }
