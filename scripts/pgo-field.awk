# scripts/pgo-field.awk: a scene for the optimised build's training run
# (scripts/pgo-train): a 64 x 64 field of objects of every kind over a
# plane, one flow mapping per line with its transform, as scene files made
# by programs are written. The gallery's scenes are a few kilobytes each;
# this one (some 700 KB) trains the reading of big files as well.
#
#   awk -f scripts/pgo-field.awk > field.yaml
#
# The numbers come from a fixed linear congruential generator.
function rnd() { seed = (seed * 1103515245 + 12345) % 2147483648; return seed / 2147483648 }
function turn() {
    return sprintf("transform: [rotate_y: %d, rotate_x: %d, scale: %.2f, translate: [%g, %.2f, %g]]",
                   int(rnd() * 360), int(rnd() * 90), 0.6 + 0.4 * rnd(), x, 0.5 + rnd(), z)
}
BEGIN {
    seed = 2027
    print "image: {width: 320, height: 180, samples: 1, depth: 4}"
    print "camera: {eye: [0, 40, 70], look_at: [0, 0, 0], fov: 60}"
    print "ambient: 0.15"
    print "lights:"
    print "  - {type: point, position: [30, 80, 50], color: 0.7}"
    print "  - {type: spot, position: [-20, 40, 10], look_at: [0, 0, 0], inner_angle: 25, outer_angle: 35, color: 0.5}"
    print "materials:"
    print "  red: {color: [0.8, 0.2, 0.15], specular: 0.4, shininess: 30}"
    print "  steel: {color: [0.6, 0.6, 0.65], reflect: 0.4, specular: 0.8, shininess: 80}"
    print "  glass: {color: [0.9, 0.95, 1], transmit: 0.8, ior: 1.5, specular: 0.9, shininess: 120}"
    print "  green: {color: [0.2, 0.7, 0.3]}"
    print "objects:"
    print "  - {type: plane, point: [0, 0, 0], normal: [0, 1, 0], material: {color: [0.5, 0.5, 0.5]}}"
    split("red steel glass green", names, " ")
    for (i = 0; i < 64; i++)
        for (j = 0; j < 64; j++) {
            x = -48 + 1.5 * i; z = -48 + 1.5 * j
            m = names[1 + int(rnd() * 4)]
            if (rnd() < 0.1)
                m = sprintf("{color: [%.2f, %.2f, %.2f]}", rnd(), rnd(), rnd())
            k = (i * 64 + j) % 7
            if (k == 0)
                printf "  - {type: sphere, center: [0, 0, 0], radius: %.2f, material: %s, %s}\n", 0.3 + 0.3 * rnd(), m, turn()
            else if (k == 1)
                printf "  - {type: box, min: [-0.4, -0.3, -0.2], max: [0.4, 0.3, %.2f], material: %s, %s}\n", 0.2 + 0.3 * rnd(), m, turn()
            else if (k == 2)
                printf "  - {type: cylinder, base: [0, -0.4, 0], radius: 0.3, height: %.2f, material: %s, %s}\n", 0.5 + 0.5 * rnd(), m, turn()
            else if (k == 3)
                printf "  - {type: cone, base: [0, -0.4, 0], radius: 0.4, top_radius: %.2f, height: 0.8, material: %s, %s}\n", 0.3 * rnd(), m, turn()
            else if (k == 4)
                printf "  - {type: torus, center: [0, 0, 0], major_radius: 0.35, minor_radius: %.2f, material: %s, %s}\n", 0.05 + 0.1 * rnd(), m, turn()
            else if (k == 5)
                printf "  - {type: polyhedron, preset: tetrahedron, center: [0, 0, 0], radius: 0.5, material: %s, %s}\n", m, turn()
            else
                printf "  - {type: csg, op: difference, material: %s, %s, objects: [{type: sphere, center: [0, 0, 0], radius: 0.5}, {type: box, min: [-0.3, -0.6, -0.3], max: [0.3, 0.6, 0.3]}]}\n", m, turn()
        }
}
