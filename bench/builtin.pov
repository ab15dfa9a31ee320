// glint's built-in scene (scenes/seed.yaml, the assignment's nine objects)
// written for POV-Ray 3.7, for benchmark row 1 (bench/README.md). Run it
// from the repository root, where the textures are (`make` writes them):
//
//   povray +Ibench/builtin.pov +W500 +H500 +AM1 +A0.0 +R2 -J -D +O/tmp/pov.png
//
// Coordinates are glint's, unchanged. glint is right-handed and POV-Ray
// left-handed, so the camera's right vector is -x: after look_at turns the
// camera round to face -z it points along +x, and the picture is not
// mirrored. At 500x500 the render differs from `glint -o glint.png` by
// less than one level in 256 on average, mostly along edges.
//
// How glint's material model (src/shade/material.h) maps onto POV-Ray's:
// - Colours are display values and nothing is gamma-corrected (glint's
//   `transfer: none`): assumed_gamma srgb makes POV-Ray work in the same
//   space it writes, so colours and PNG textures pass through as given.
// - ambient: the scene's 0.2 is ambient_light; every finish has ambient 1
//   and diffuse 1 (glint's material defaults); specular/shininess are
//   phong/phong_size (glint's Phong highlight on the reflected light vector).
// - reflect adds the mirrored ray on top of the local colour, as POV-Ray's
//   plain `reflection` does. The point light has no fall-off.
// - Transmission: glint weights the local colour by 1 - transmit and passes
//   transmit * tint of what lies behind. For the glass (tint 1) that is
//   POV's transmit 0.95, with Fresnel reflection (glint uses Schlick's
//   approximation, POV the full formula) taking its share. For the red
//   sphere, filter f and transmit t are chosen so that f * colour + t
//   matches 0.7 * tint: f = 0.45, t = 0.2725 (exact in red and green, 0.3625
//   for glint's 0.315 in blue). Shadow rays pass through both, filtered,
//   in both renderers; neither traces caustics.
// - Recursion: glint's depth 5 means five bounces after the primary ray,
//   POV-Ray's max_trace_level counts the primary ray too, hence 6. POV-Ray
//   keeps its default adc_bailout (it stops rays worth less than 1/255).
// - Textures are bilinear (interpolate 2). glint's sphere longitude puts
//   u = 0.5 at +z and runs the other way round from POV-Ray's spherical map,
//   hence the mirror and quarter turn. The flag is a planar map on a unit
//   square, scaled to 12 x 8. The chequer is 3D in POV-Ray: the tall y
//   scale keeps the floor (y = -15) inside one layer, and the squares'
//   parity matches glint's scale [8, 32] over the 40 x 160 quad.
#version 3.7;

global_settings { assumed_gamma srgb ambient_light rgb 0.2 max_trace_level 6 }

camera {
  perspective
  location <0, 0, 0>
  right -x * image_width / image_height
  up y
  angle 28.072487 // horizontal: 2 atan(10 / 40)
  look_at <0, 0, -1>
}

background { rgb 0 }

light_source { <40, 50, -45> color rgb 1 }

// 1. reflective blue sphere
sphere { <-5, 0, -90>, 15
  pigment { rgb <0.05, 0.15, 0.9> }
  finish { ambient 1 diffuse 1 phong 1 phong_size 80 reflection 0.8 }
}

// 2. refractive glass sphere
sphere { <5, 5, -70>, 4
  pigment { rgbt <1, 1, 1, 0.95> }
  finish {
    ambient 1 diffuse 1 phong 1 phong_size 200
    reflection { 0, 0.95 fresnel on }
    conserve_energy
  }
  interior { ior 1.5 }
}

// 3. transparent sphere (no refraction), lighter red shadow
sphere { <10, 10, -60>, 3
  pigment { rgbft <0.95, 0.25, 0.2, 0.45, 0.2725> }
  finish { ambient 1 diffuse 1 phong 0.8 phong_size 100 }
}

// 4. image-textured sphere (the globe), made at the origin and moved so the
// texture moves with it
sphere { 0, 3
  pigment {
    image_map { png "scenes/textures/globe.png" map_type 1 interpolate 2 }
    scale <-1, 1, 1>
    rotate -90 * y
  }
  finish { ambient 1 diffuse 1 phong 0.4 phong_size 40 }
  translate <8, -11, -55>
}

// 5. green capped cylinder
cylinder { <10, -15, -80>, <10, -5, -80>, 3
  pigment { rgb <0.1, 0.75, 0.2> }
  finish { ambient 1 diffuse 1 phong 0.6 phong_size 60 }
}

// 6. yellow box
box { <-2, -15, -75>, <4, -9, -69>
  pigment { rgb <0.95, 0.85, 0.1> }
  finish { ambient 1 diffuse 1 phong 0.5 phong_size 40 }
}

// 7. orange cuboid, turned 30 degrees about y (the same matrix as glint's
// rotate_y: 30), standing on the floor
box { <-2, -6, -2>, <2, 6, 2>
  pigment { rgb <1, 0.5, 0.05> }
  finish { ambient 1 diffuse 1 phong 0.5 phong_size 40 }
  rotate 30 * y
  translate <-14, -9, -80>
}

// 8. chequered floor: the quad x in [-20, 20], z in [-40, -200], squares of 5
polygon { 5, <-20, -15, -40>, <20, -15, -40>, <20, -15, -200>, <-20, -15, -200>, <-20, -15, -40>
  pigment { checker rgb <0.92, 0.92, 0.88>, rgb <0.12, 0.14, 0.2> scale <5, 1000, 5> }
  finish { ambient 1 diffuse 1 phong 0.1 phong_size 20 }
}

// 9. the 3:2 flag behind the transparent sphere, origin (9, 8, -100)
polygon { 5, <0, 0, 0>, <1, 0, 0>, <1, 1, 0>, <0, 1, 0>, <0, 0, 0>
  pigment { image_map { png "scenes/textures/flag.png" map_type 0 interpolate 2 once } }
  finish { ambient 1 diffuse 1 }
  scale <12, 8, 1>
  translate <9, 8, -100>
}
