# fold1_arc.awk - fold1 (CASES.md) with K = 0, the paper's model, in closed
# form: the fold band is a circular arc (constant curvature, MODEL.md 2),
# so the sheet is a rigid face on a torsional spring of stiffness
# k = D L / w, and equilibrium is one scalar equation in the bend angle
# phi > 0 (downwards):
#   Pi(phi) = k phi^2 / 2 - P (w (1 - cos phi) / phi + a sin phi),
#   k phi = P (w (phi sin phi - 1 + cos phi) / phi^2 + a cos phi),
# a = 0.023 m from the band's free edge (x = 0.035) to the load, P = 4 N
# times the load factor.  Solved by Newton to machine precision; the probe
# at b = 0.025 m beyond the band moves by
#   ux = w sin(phi)/phi + b cos(phi) - (w + b),  uz = -(w (1 - cos phi)/phi + b sin phi),
# and the fold angle is theta = -phi (the study's sign: the fold runs in +y,
# its left side is the clamped face).
# usage: awk -f tests/fold1_arc.awk   (prints a reference CSV, provenance first)
BEGIN {
    E = 15.2e6; nu = 0.45; h = 1.8e-3; w = 0.01; L = 0.03; P0 = 4.0; a = 0.023; b = 0.025
    D = E * h * h * h / (12 * (1 - nu * nu)); k = D * L / w
    print "# fold1 with K = 0 (circular-arc fold, the paper's model) in closed form"
    print "# source: tests/fold1_arc.awk: Newton on the one-variable equilibrium of a rigid face on a"
    print "#   torsional spring k = D L / w with the arc's chord; D = E h^3 / (12 (1 - nu^2))"
    print "# kind: simulated (closed-form solution of the K = 0 model)"
    print "# units: load factor 1, fold angle rad, displacements m"
    print "# columns: load_factor, theta1, probe1_ux, probe1_uz"
    print "load_factor,theta1,probe1_ux,probe1_uz"
    phi = 0.3
    for (i = 1; i <= 16; i++) {
        P = P0 * i / 16
        for (it = 0; it < 100; it++) {
            s = sin(phi); c = cos(phi)
            g = w * (phi * s - 1 + c) / (phi * phi) + a * c
            dg = w * (phi * phi * c - 2 * phi * s + 2 * (1 - c)) / (phi * phi * phi) - a * s
            r = k * phi - P * g
            dphi = -r / (k - P * dg)
            phi += dphi
            if (dphi < 0 ? -dphi < 1e-15 : dphi < 1e-15) break
        }
        s = sin(phi); c = cos(phi)
        printf "%.4f,%.15e,%.15e,%.15e\n", i / 16, -phi, w * s / phi + b * c - (w + b), -(w * (1 - c) / phi + b * s)
    }
}
