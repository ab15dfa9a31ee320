// bench/lights.yaml for POV-Ray 3.7: a spot light and an area light.
// tests/test_pov.c renders both and reports the mean difference; by hand:
//
//   povray +Ibench/lights.pov +W320 +H240 +AM1 +A0.0 +R2 -J -D +O/tmp/pov.png
//
// The mapping of glint's model is that of bench/builtin.pov (colours pass
// through unchanged, finish ambient 1 and diffuse 1, phong for specular).
// The lights:
// - glint's spot (inner_angle 15, outer_angle 25) is POV-Ray's spotlight
//   with radius 15, falloff 25 and tightness 0: both smooth the edge with
//   t^2 (3 - 2t) in the cosine of the angle.
// - glint's area light is an N x N grid of samples, each jittered within
//   its cell of edge / N; POV-Ray's puts N lights from one end of each axis
//   to the other and jitters each within edge / (N - 1). Axes of
//   edge (N - 1) / N (1.6 for glint's 2 with N = 5) cover the same
//   rectangle. area_illumination makes diffuse and highlights come from
//   every sample, as in glint.
#version 3.7;

global_settings { assumed_gamma srgb ambient_light rgb 0.1 }

camera {
  perspective
  location <0, 3, 8>
  right -x * image_width / image_height
  up y
  angle 50
  look_at <0, 0.8, 0>
}

background { rgb 0 }

light_source { <3, 5, 2> color rgb <1.0, 0.85, 0.6>
  spotlight point_at <0.5, 0, 0> radius 15 falloff 25 tightness 0
}

light_source { <-2, 5, 3> color rgb 0.6
  area_light <1.6, 0, 0>, <0, 0, 1.6>, 5, 5
  jitter
  area_illumination on
}

plane { y, 0
  pigment { rgb 0.8 }
  finish { ambient 1 diffuse 1 }
}

sphere { <-0.8, 1, 0>, 1
  pigment { rgb <0.85, 0.2, 0.15> }
  finish { ambient 1 diffuse 1 phong 0.6 phong_size 40 }
}

box { <0.6, 0, -0.8>, <1.8, 1.2, 0.4>
  pigment { rgb <0.2, 0.35, 0.8> }
  finish { ambient 1 diffuse 1 phong 0.3 phong_size 20 }
}
