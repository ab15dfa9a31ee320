# bench/tori.awk: the scene of benchmark row 6 (bench/README.md), 10,000
# tori and 1,000 csg objects over a plane, written as a glint scene
# (-v format=yaml) or the same scene for POV-Ray (-v format=pov).
#
#   awk -v format=yaml -f bench/tori.awk > tori.yaml
#   awk -v format=pov -f bench/tori.awk > tori.pov
#
# A 100 x 100 grid of tori (major radius 0.32, minor 0.1), each turned by
# pseudo-random angles about x and then y, in four colours; above them a
# 40 x 25 grid of csg objects, each a cube intersected with a sphere with a
# rod-shaped hole cut through it (the hole has its own darker material).
# The numbers come from a fixed linear congruential generator, so both
# files always describe the same scene. Coordinates are glint's; the POV
# camera's right vector is -x, as in builtin.pov, so the picture is not
# mirrored, and POV-Ray's rotate <a, 0, 0> is the same matrix as glint's
# rotate_x: a. At 480x270 the two pictures differ by 0.15 levels in 256 on
# average.
function rnd() { seed = (seed * 1103515245 + 12345) % 2147483648; return seed / 2147483648 }
function yaml_head() {
    print "image: {width: 1920, height: 1080, samples: 1, depth: 3}"
    print "camera: {eye: [0, 28, 52], look_at: [0, 0, -8], fov: 70}"
    print "ambient: 0.2"
    print "lights: [{type: point, position: [20, 60, 40], color: 0.9}]"
    print "materials:"
    for (k = 0; k < 4; k++)
        printf "  c%d: {color: [%s], specular: 0.5, shininess: 40}\n", k, col[k]
    print "  ivory: {color: [0.95, 0.92, 0.82], specular: 0.5, shininess: 60}"
    print "  dark: {color: [0.2, 0.2, 0.25], specular: 0.2, shininess: 20}"
    print "  ground: {color: [0.6, 0.6, 0.6]}"
    print "objects:"
    print "  - {type: plane, point: [0, 0, 0], normal: [0, 1, 0], material: ground}"
}
function pov_head() {
    print "#version 3.7;"
    print "global_settings { assumed_gamma srgb ambient_light rgb 0.2 max_trace_level 4 }"
    print "camera { perspective location <0, 28, 52> right -x * image_width / image_height"
    print "  up y angle 70 look_at <0, 0, -8> }"
    print "background { rgb 0 }"
    print "light_source { <20, 60, 40> color rgb 0.9 }"
    for (k = 0; k < 4; k++)
        printf "#declare C%d = texture { pigment { rgb <%s> } finish { ambient 1 diffuse 1 phong 0.5 phong_size 40 } }\n", k, col[k]
    print "#declare Ivory = texture { pigment { rgb <0.95, 0.92, 0.82> } finish { ambient 1 diffuse 1 phong 0.5 phong_size 60 } }"
    print "#declare Dark = texture { pigment { rgb <0.2, 0.2, 0.25> } finish { ambient 1 diffuse 1 phong 0.2 phong_size 20 } }"
    print "plane { y, 0 texture { pigment { rgb 0.6 } finish { ambient 1 diffuse 1 } } }"
}
BEGIN {
    seed = 12345
    col[0] = "0.85, 0.2, 0.1"; col[1] = "0.95, 0.8, 0.15"
    col[2] = "0.15, 0.7, 0.3"; col[3] = "0.2, 0.4, 0.9"
    if (format == "yaml") yaml_head(); else if (format == "pov") pov_head()
    else { print "tori.awk: -v format=yaml or -v format=pov" > "/dev/stderr"; exit 2 }
    for (i = 0; i < 100; i++)
        for (j = 0; j < 100; j++) {
            x = -49.5 + i; z = -49.5 + j
            ax = int(rnd() * 180); ay = int(rnd() * 360); k = int(rnd() * 4)
            if (format == "yaml")
                printf "  - {type: torus, center: [0, 0, 0], major_radius: 0.32, minor_radius: 0.1, material: c%d, transform: [rotate_x: %d, rotate_y: %d, translate: [%g, 0.42, %g]]}\n", k, ax, ay, x, z
            else
                printf "torus { 0.32, 0.1 rotate <%d, 0, 0> rotate <0, %d, 0> translate <%g, 0.42, %g> texture { C%d } }\n", ax, ay, x, z, k
        }
    for (i = 0; i < 40; i++)
        for (j = 0; j < 25; j++) {
            x = -48.75 + 2.5 * i; z = -48.75 + 2.5 * j
            if (format == "yaml") {
                printf "  - {type: csg, op: difference, transform: [translate: [%g, 1.3, %g]], objects: [", x, z
                printf "{type: csg, op: intersection, material: ivory, objects: [{type: box, min: [-0.4, -0.4, -0.4], max: [0.4, 0.4, 0.4]}, {type: sphere, center: [0, 0, 0], radius: 0.54}]}, "
                printf "{type: cylinder, base: [0, -1, 0], radius: 0.2, height: 2, material: dark}]}\n"
            } else {
                printf "difference { intersection { box { <-0.4, -0.4, -0.4>, <0.4, 0.4, 0.4> } sphere { <0, 0, 0>, 0.54 } texture { Ivory } } "
                printf "cylinder { <0, -1, 0>, <0, 1, 0>, 0.2 texture { Dark } } translate <%g, 1.3, %g> }\n", x, z
            }
        }
}
