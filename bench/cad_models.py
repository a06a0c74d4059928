#!/usr/bin/env python3
"""Mechanical / CAD-like whole models for the atlas benches, made here by constructive solid
geometry with pip `manifold3d` (3.5.4): gears, brackets, plates, blades, assemblies of several
pieces, thin shells, fasteners, shafts, pulleys, beams, pipes, knobs, heat sinks and so on.

Why: scans and sculpted models (the shared closed/ set) are smooth and uniformly meshed; CAD
exports are not. A CAD STL/OBJ has large flat faces fan-triangulated into long thin triangles,
cylinders of 32-96 segments (each side a pair of slivers from cap to cap), sharp 90-degree edges,
many holes (genus), thin walls and several closed pieces in one file. These models stand for
that. A few (`*_uniform`, `*_refined`) are the same kind of solid remeshed finely, standing for
CAD meshed uniformly.

Every model is a closed triangle mesh: each piece watertight and edge-manifold (each edge used by
exactly two faces, in opposite directions), pieces kept apart (no shared or coincident vertices),
no zero-area faces. Vertices are indexed as manifold3d makes them (exactly equal positions merged)
and written as float64 with %.17g, so the OFF files are the same bytes on every run (manifold3d is
deterministic; the few randomised details, such as which holes of a pattern are left out or the
heights of a heat sink's fins, come from random.Random seeded by SEED and the model's name).

Held out: exactly a quarter of the models, fixed by name in HELD_OUT and spread over the kinds
(a gear, a plate, an assembly, a shell, a blade, a pipe, a rod, a remeshed one), are
`held_out=True`. Keep them out of any tuning; report them apart.

Nothing is stored in the repository and no licences are involved: every mesh is generated here
and written once into a cache folder.

    from cad_models import cad_models
    for name, off_path, held_out in cad_models(pathlib.Path(cache)): ...

    python3 bench/cad_models.py [FOLDER]   writes all (default ~/.cache/straightest-param/bench/cad)
                                           and prints name, kind, pieces, vertices, faces, held_out
"""
import math
import pathlib
import random
import sys
import zlib

import numpy as np
from manifold3d import CrossSection, JoinType, Manifold, OpType

SEED = 20240611
# A quarter of the models, one or so per kind; fixed by name, never by what they score.
HELD_OUT = {
    "gear_z56_web",
    "flange_bolt_circle",
    "bearing_set",
    "tank_shell",
    "fan_rotor",
    "pipe_tee",
    "connecting_rod",
    "housing_uniform",
}


# ---------------------------------------------------------------------------------------------
# Small helpers. Cylinders are along +z from z=0 unless centred; `seg` is the number of segments
# around (what a CAD exporter's chord tolerance gives: 32-96).

def cyl(h, r, seg=48, center=False, r2=-1.0):
    return Manifold.cylinder(h, r, r2, seg, center)


def box(x, y, z, center=False):
    return Manifold.cube((x, y, z), center)


def union(parts):
    out = parts[0]
    for p in parts[1:]:
        out = out + p
    return out


def minus(solid, cutters):
    for c in cutters:
        solid = solid - c
    return solid


def pieces(parts):
    """Several closed pieces in one mesh (they must not touch)."""
    return Manifold.compose(parts)


def circle(r, seg=48):
    return CrossSection.circle(r, seg)


def polygon(points):
    return CrossSection([np.asarray(points, dtype=np.float64)])


def stadium(length, r, seg=32):
    """A slot: two half circles of radius r, centres `length` apart on x, centred."""
    return CrossSection.batch_hull([circle(r, seg).translate((-length / 2, 0)),
                                    circle(r, seg).translate((length / 2, 0))])


def rounded_rect(w, h, r, seg=32):
    return CrossSection.batch_hull([circle(r, seg).translate((sx * (w / 2 - r), sy * (h / 2 - r)))
                                    for sx in (-1, 1) for sy in (-1, 1)])


def hexagon(across_flats):
    r = across_flats / 2 / math.cos(math.pi / 6)
    return polygon([(r * math.cos(math.pi / 3 * k), r * math.sin(math.pi / 3 * k))
                    for k in range(6)])


def on_x(m):
    """A solid built along +z, turned to lie along +x."""
    return m.rotate((0, 90, 0))


def on_y(m):
    """A solid built along +z, turned to lie along +y."""
    return m.rotate((-90, 0, 0))


def along_y(m):
    """A solid extruded from an x-y profile along +z, turned so that the profile's y is z and the
    extrusion runs along +y."""
    return m.rotate((90, 0, 0)).mirror((0, 1, 0))


def chamfered_hex(af, h):
    """A hex prism (across flats af, height h) with its corners chamfered at 30 degrees at both
    ends, as nuts and bolt heads are."""
    R, r0 = af / 2 / math.cos(math.pi / 6), 0.95 * af / 2
    k = (R - r0) / 1.5
    # (turned half a segment so that no edge of the cone runs through a corner of the hexagon)
    lower = cyl(h / 2 + 1.5, r0 - k, 96, r2=r0 + (h / 2 + 0.5) * k)
    lower = lower.rotate((0, 0, 180 / 96)).translate((0, 0, -1))
    upper = lower.mirror((0, 0, 1)).translate((0, 0, h))
    return hexagon(af).extrude(h) ^ (lower + upper)


# ---------------------------------------------------------------------------------------------
# Profiles

def gear_outline(z, m, pressure_deg=20.0, flank=7, tip=3, root=4):
    """Involute spur gear outline (module m, z teeth), counter-clockwise; no undercut."""
    rp = m * z / 2
    rb = rp * math.cos(math.radians(pressure_deg))
    ra, rf = rp + m, rp - 1.25 * m
    inv = lambda a: math.tan(a) - a  # noqa: E731
    ap = math.radians(pressure_deg)
    psi = math.pi / (2 * z)

    def beta(r):  # half the tooth's angular width at radius r >= rb
        return psi + inv(ap) - inv(math.acos(min(1.0, rb / r)))

    r0 = max(rb, rf)
    b0 = beta(r0)
    rs = np.linspace(r0, ra, flank)
    pts = []
    for k in range(z):
        c = 2 * math.pi * k / z
        roots = np.linspace(c - 2 * math.pi / z + b0, c - b0, root + 2)
        if rf >= rb:
            roots = roots[1:-1]
        pts += [(rf, a) for a in roots]
        pts += [(r, c - beta(r)) for r in rs]
        bt = beta(ra)
        pts += [(ra, a) for a in np.linspace(c - bt, c + bt, tip + 2)[1:-1]]
        pts += [(r, c + beta(r)) for r in rs[::-1]]
    return polygon([(r * math.cos(a), r * math.sin(a)) for r, a in pts])


def naca4(code, chord, n=40):
    """NACA 4-digit airfoil, closed trailing edge, counter-clockwise, quarter chord at origin."""
    mm, p, t = int(code[0]) / 100, int(code[1]) / 10, int(code[2:]) / 100
    beta = np.linspace(0, math.pi, n)
    x = (1 - np.cos(beta)) / 2
    yt = 5 * t * (0.2969 * np.sqrt(x) - 0.1260 * x - 0.3516 * x ** 2 + 0.2843 * x ** 3
                  - 0.1036 * x ** 4)
    yc = np.where(x < p, mm / p ** 2 * (2 * p * x - x ** 2),
                  mm / (1 - p) ** 2 * ((1 - 2 * p) + 2 * p * x - x ** 2))
    dyc = np.where(x < p, 2 * mm / p ** 2 * (p - x), 2 * mm / (1 - p) ** 2 * (p - x))
    th = np.arctan(dyc)
    xu, yu = x - yt * np.sin(th), yc + yt * np.cos(th)
    xl, yl = x + yt * np.sin(th), yc - yt * np.cos(th)
    # upper from trailing edge to leading edge, then lower back (counter-clockwise)
    xs = np.concatenate([xu[::-1], xl[1:-1]])
    ys = np.concatenate([yu[::-1], yl[1:-1]])
    return polygon(np.column_stack([(xs - 0.25) * chord, ys * chord]))


def thread_section(r_root, r_crest, seg=48):
    """Cross-section of a single-start V thread: radius goes root to crest and back once around,
    so that an extrusion twisted 360 degrees per pitch is a true helical thread."""
    pts = []
    for k in range(seg):
        s = k / seg
        tri = 1 - abs(2 * s - 1)  # 0 -> 1 -> 0
        r = r_root + (r_crest - r_root) * min(1.0, 1.25 * tri)
        a = 2 * math.pi * s
        pts.append((r * math.cos(a), r * math.sin(a)))
    return polygon(pts)


# ---------------------------------------------------------------------------------------------
# Models: each returns (kind, Manifold); rng is random.Random(SEED, name)

def gear_z17(rng):
    g = gear_outline(17, 2.0).extrude(12)
    return "gear", g - cyl(14, 4, 48).translate((0, 0, -1))


def gear_z30_keyway(rng):
    g = gear_outline(30, 1.5).extrude(10)
    hub = cyl(8, 12, 64).translate((0, 0, 9.5))
    bore = cyl(22, 6, 64).translate((0, 0, -2))
    key = box(4, 6, 22).translate((-2, 4, -2))
    chamfer = cyl(2, 8, 64, r2=6).translate((0, 0, -1.2))
    return "gear", minus(g + hub, [bore, key, chamfer])


def gear_z56_web(rng):
    g = gear_outline(56, 1.0).extrude(8)
    web = cyl(2.5, 23, 96) - cyl(2.5, 11, 64)  # thinner between hub and rim, both faces
    holes = [cyl(12, 4.5, 32).translate((17 * math.cos(a), 17 * math.sin(a), -2))
             for a in np.linspace(0, 2 * math.pi, 6, endpoint=False)]
    cuts = [web.translate((0, 0, -0.5)), web.translate((0, 0, 6)),
            cyl(12, 5, 48).translate((0, 0, -2))]
    return "gear", minus(g, cuts + holes)


def bracket_l_holes(rng):
    base = box(60, 40, 5)
    wall = box(5, 40, 45)
    b = base + wall
    cuts = [cyl(7, 3.3, 48).translate((x, y, -1)) for x in (20, 48) for y in (10, 30)]
    cuts += [on_x(cyl(7, 3.3, 48)).translate((-1, y, z)) for y in (10, 30) for z in (20, 36)]
    cuts += [on_x(stadium(10, 2.2, 32).extrude(7)).translate((-1, 20, 28))]  # a vertical slot
    return "bracket", minus(b, cuts)


def channel_u(rng):
    prof = polygon([(0, 0), (40, 0), (40, 30), (37, 30), (37, 3), (3, 3), (3, 30), (0, 30)])
    ch = along_y(prof.extrude(120))  # profile in x-z, 120 long in y
    slots = [stadium(8, 2.5, 32).rotate(90).extrude(5).translate((20, y, -1))
             for y in np.linspace(15, 105, 5)]
    holes = [on_x(cyl(42, 3.3, 32)).translate((-1, y, 20)) for y in (30, 90)]
    return "bracket", minus(ch, slots + holes)


def bracket_filleted(rng):
    t, L, W, H, r, ro = 8.0, 70.0, 50.0, 50.0, 8.0, 3.5  # ro < t / 2
    ell = CrossSection.square((L, t)) + CrossSection.square((t, H))
    # the inner fillet (radius r) and the outer rounds (radius ro) of a CAD part: round offsets
    ell = ell.offset(r, JoinType.Round, 2.0, 64).offset(-r, JoinType.Round, 2.0, 64)
    ell = ell.offset(-ro, JoinType.Round, 2.0, 48).offset(ro, JoinType.Round, 2.0, 48)
    b = along_y(ell.extrude(W))
    gusset = along_y(polygon([(t - 1, t - 1), (t + 28, t - 1), (t - 1, t + 28)]).extrude(5))
    b = union([b, gusset.translate((0, 8, 0)), gusset.translate((0, W - 13, 0))])
    holes = [cyl(t + 2, 4, 48).translate((x, y, -1))
             for x in (35, 58) for y in (W / 2 - 12, W / 2 + 12)]
    holes += [on_x(cyl(t + 2, 4, 48)).translate((-1, W / 2, z)) for z in (26, 41)]
    return "bracket", minus(b, holes)


def plate_hole_pattern(rng):
    p = rounded_rect(150, 100, 6, 48).extrude(6)
    cuts = []
    for i in range(6):
        for j in range(4):
            if rng.random() < 0.15:
                continue  # a few holes left out, seeded
            cuts.append(cyl(8, 2.6, 32).translate((-50 + 20 * i, -30 + 20 * j, -1)))
    cuts += [cyl(8, 4.5, 48).translate((sx * 66, sy * 41, -1)) for sx in (-1, 1) for sy in (-1, 1)]
    # counterbores on the corner holes
    cuts += [cyl(3, 7.5, 48).translate((sx * 66, sy * 41, 4)) for sx in (-1, 1) for sy in (-1, 1)]
    return "plate", minus(p, cuts)


def plate_countersunk(rng):
    p = box(120, 80, 8, center=True).translate((0, 0, 4))
    pocket = rounded_rect(60, 30, 5, 32).extrude(5).translate((0, 0, 4))
    cuts = [pocket]
    for x in (-48, -24, 24, 48):
        for y in (-28, 28):
            cuts.append(cyl(10, 3.2, 40).translate((x, y, -1)))
            cuts.append(cyl(3.3, 3.2, 40, r2=6.5).translate((x, y, 4.71)))
    cuts.append(on_x(cyl(130, 1.5, 32)).translate((-65, 0, 2.6)))  # a cross-drilled passage
    return "plate", minus(p, cuts)


def flange_bolt_circle(rng):
    f = cyl(10, 60, 96) + cyl(25, 30, 96).translate((0, 0, 9.5))
    f = f + (cyl(4, 36, 96, r2=30).translate((0, 0, 9.5)))  # a conical fillet at the hub's foot
    cuts = [cyl(40, 20, 96).translate((0, 0, -1))]
    cuts += [cyl(12, 5.5, 32).translate((45 * math.cos(a), 45 * math.sin(a), -1))
             for a in np.linspace(0, 2 * math.pi, 8, endpoint=False)]
    ring = cyl(2, 52, 96).translate((0, 0, -1)) - cyl(2, 48, 96).translate((0, 0, -1))
    cuts.append(ring ^ cyl(1.6, 60, 96).translate((0, 0, -0.6)))  # a sealing groove on the face
    return "plate", minus(f, cuts)


def turbine_blade(rng):
    foil = naca4("4412", 40, 45)
    blade = foil.extrude(120, 40, 35.0, (0.55, 0.55)).translate((0, 0, 12))
    root = box(48, 20, 14, center=True).translate((0, 0, 6))
    root = minus(root, [on_x(cyl(60, 3, 32)).translate((-30, s * 5, 5)) for s in (-1, 1)])
    platform = rounded_rect(56, 26, 3, 24).extrude(3).translate((0, 0, 11))
    return "blade", union([blade, root, platform])


def fan_rotor(rng):
    hub = cyl(30, 18, 96) + Manifold.sphere(18, 64).scale((1, 1, 0.6)).translate((0, 0, 30))
    hub = hub - cyl(40, 5, 48).translate((0, 0, -1))
    foil = naca4("6409", 26, 30)
    blade = foil.extrude(55, 24, 40.0, (0.6, 0.6)).translate((0, 0, 12))
    blade = blade.rotate((0, 0, 90)).rotate((-90, 0, 0))  # radial along +y
    parts = [hub] + [blade.rotate((0, 0, 360 / 7 * k)).translate((0, 0, 15)) for k in range(7)]
    return "blade", union(parts)


def bolt_nut_washer(rng):
    pitch, L = 2.0, 34.0
    n = L + 1
    shank = thread_section(4.0, 5.0, 48).extrude(n, int(n / pitch * 6), 360 * n / pitch)
    tip = cyl(3, 3.3, 48, r2=6.3).translate((0, 0, -1)) + cyl(L, 6.3, 48).translate((0, 0, 1.9))
    shank = shank ^ tip  # chamfered end
    bolt = shank + chamfered_hex(16, 6.5).translate((0, 0, L))
    washer = (cyl(2, 10, 48) - cyl(4, 5.4, 48).translate((0, 0, -1))).translate((0, 0, L - 2.2))
    nut = chamfered_hex(16, 8) - cyl(10, 5.3, 48).translate((0, 0, -1))
    nut = nut.rotate((0, 0, 15)).translate((0, 0, 8))
    return "assembly", pieces([bolt, washer, nut])


def bearing_set(rng):
    # inner ring, outer ring and 10 balls: separate pieces, not touching
    seg = 96
    groove = circle(4.2, 32).translate((22, 0)).revolve(seg)
    inner = polygon([(12, -6), (18.5, -6), (18.5, 6), (12, 6)]).revolve(seg) - groove
    outer = polygon([(25.5, -6), (32, -6), (32, 6), (25.5, 6)]).revolve(seg) - groove
    balls = [Manifold.sphere(4.0, 24).translate((22 * math.cos(a), 22 * math.sin(a), 0))
             for a in np.linspace(0, 2 * math.pi, 10, endpoint=False)]
    return "assembly", pieces([inner, outer] + balls)


def chain_links(rng):
    R, r, straight, gap = 6.0, 1.8, 14.0, 1.0

    def link():
        half = circle(r, 24).translate((R, 0)).revolve(48, 180)  # half a torus, y >= 0
        sides = [on_y(cyl(straight, r, 24, center=True)).translate((s * R, 0, 0)) for s in (-1, 1)]
        return union([half.translate((0, straight / 2, 0)),
                      half.rotate((0, 0, 180)).translate((0, -straight / 2, 0))] + sides)
    pitch = 2 * (R + straight / 2) - 2 * r - gap  # each link through the next, not touching
    return "assembly", pieces([link().translate((0, 0, 0)),
                               link().rotate((0, 90, 0)).translate((0, pitch, 0)),
                               link().translate((0, 2 * pitch, 0))])


def hollow_box_shell(rng):
    def rounded_box(a, b, c, r, seg):
        return Manifold.batch_hull([Manifold.sphere(r, seg).translate(
                                    (sx * (a / 2 - r), sy * (b / 2 - r), sz * (c / 2 - r)))
                                    for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
    outer = rounded_box(100, 80, 60, 6, 32)
    inner = rounded_box(100 - 3, 80 - 3, 60 - 3, 4.5, 32)  # 1.5 mm wall: 1.5% of the length
    return "shell", outer - inner


def cup(rng):
    body = cyl(50, 30, 96)
    cavity = cyl(60, 29.4, 96).translate((0, 0, 1.2))  # 0.6 mm wall on a 60 mm cup
    handle = circle(2.5, 24).translate((12, 0)).revolve(48, 180)  # a C in x-y, y >= 0
    handle = handle.rotate((0, 0, -90)).rotate((90, 0, 0)).translate((29.5, 0, 25))
    return "shell", (body + handle) - cavity


def housing_box(rng):
    W, D, H, t = 90, 60, 40, 2.5
    outer = rounded_rect(W, D, 6, 48).extrude(H)
    inner = rounded_rect(W - 2 * t, D - 2 * t, 3.5, 48).extrude(H).translate((0, 0, t))
    bosses = []
    for sx in (-1, 1):
        for sy in (-1, 1):
            p = (sx * (W / 2 - 9), sy * (D / 2 - 9), 0)
            bosses.append((cyl(H - 4, 5, 48) - cyl(H, 1.6, 32).translate((0, 0, 4))).translate(p))
    h = union([outer - inner] + bosses)
    cuts = [on_x(cyl(20, 6, 48)).translate((W / 2 - 10, 0, 20)),
            on_y(rounded_rect(20, 8, 2, 16).extrude(20)).translate((-15, -D / 2 - 10, 25)),
            cyl(10, 3, 32).translate((0, 0, -1))]
    cuts += [stadium(18, 1.2, 16).rotate(90).extrude(10).translate((-20 + 10 * k, 12, -1))
             for k in range(5)]  # vent slots in the floor
    tabs = [(rounded_rect(16, 12, 3, 24).extrude(t) - cyl(5, 2.2, 32).translate((s * 3, 0, -1)))
            .translate((s * (W / 2 + 4), 0, 0)) for s in (-1, 1)]
    return "housing", union([minus(h, cuts)] + tabs)


def tank_shell(rng):
    R, L, w, seg = 40.0, 120.0, 0.8, 96  # 0.8 mm wall: 1% of the diameter

    def capsule(r):
        return union([cyl(L, r, seg), Manifold.sphere(r, seg),
                      Manifold.sphere(r, seg).translate((0, 0, L))])
    boss = on_x(cyl(12, 8, 48)).translate((R - 4, 0, L / 2))  # a solid boss; the cavity stays shut
    return "shell", (capsule(R) + boss) - capsule(R - w)


def hex_nut(rng):
    af, h, pitch = 24.0, 13.0, 2.0
    nut = chamfered_hex(af, h)
    n = h + 2
    thread = thread_section(8.2, 6.9, 64).extrude(n, int(n / pitch * 6), -360 * n / pitch)
    sinks = [cyl(1.6, 9.0, 64, r2=7.4).translate((0, 0, -0.6)),
             cyl(1.6, 7.4, 64, r2=9.0).translate((0, 0, h - 1.0))]
    return "fastener", minus(nut, [thread.translate((0, 0, -1))] + sinks)


def stepped_shaft(rng):
    prof = [(0, 0), (9.5, 0), (10, 0.5), (10, 30), (12.5, 30), (12.5, 70), (11.4, 70), (11.4, 71.5),
            (12.5, 71.5), (12.5, 110), (16, 110), (16, 118), (12.5, 118), (12.5, 150), (9, 150),
            (9, 185), (8.5, 185.5), (0, 185.5)]
    s = polygon(prof).revolve(64)
    # keyways: slots along the axis, cut from +x (the slot's long side along z)
    key = stadium(25, 2.5, 32).rotate(90).extrude(10).rotate((0, 90, 0))
    key = key.translate((12.5 - 3.0, 0, 90))
    key2 = stadium(22, 2.0, 32).rotate(90).extrude(10).rotate((0, 90, 0))
    key2 = key2.translate((9 - 2.5, 0, 168))
    centre = cyl(8, 2.5, 32, r2=0.3).translate((0, 0, -0.5))
    return "shaft", minus(s, [key, key2, centre])


def pulley(rng):
    prof = [(6, -10), (14, -10), (14, -5), (34, -5), (34, -9), (44, -9), (44, -8), (40.5, -3),
            (40.5, 3), (44, 8), (44, 9), (34, 9), (34, 5), (14, 5), (14, 10), (6, 10)]
    p = polygon(prof).revolve(96)
    holes = [cyl(20, 5.5, 48).translate((24 * math.cos(a), 24 * math.sin(a), -10))
             for a in np.linspace(0, 2 * math.pi, 5, endpoint=False)]
    key = box(4, 5, 30).translate((-2, 4.5, -15))
    return "revolved", minus(p, holes + [key])


def i_beam(rng):
    H, B, tw, tf, r = 100, 55, 4.1, 5.7, 7
    side = CrossSection.square(((B - tw) / 2, H - 2 * tf))
    shape = CrossSection.square((B, H), True) - side.translate((tw / 2, -H / 2 + tf)) - \
        side.translate((-B / 2, -H / 2 + tf))
    # root fillets
    shape = shape.offset(r, JoinType.Round, 2.0, 32).offset(-r, JoinType.Round, 2.0, 32)
    beam = shape.extrude(240)
    holes = [on_x(cyl(20, 8, 48, center=True)).translate((0, 0, z)) for z in (40, 90, 150, 200)]
    holes += [on_y(cyl(12, 3, 32)).translate((x, H / 2 - 8, z))
              for x in (-17, 17) for z in (12, 228)]
    return "beam", minus(beam, holes)


def pipe_elbow(rng):
    Ro, Ri, Rb, leg = 15.0, 13.0, 45.0, 40.0

    def elbow(r, extra):
        # the bend and its two straight legs from the same circle, so that they meet exactly
        bend = circle(r, 48).translate((Rb, 0)).revolve(64, 90)  # from +x towards +y
        a = circle(r, 48).translate((Rb, 0)).extrude(leg + extra).rotate((90, 0, 0))  # going -y
        return union([bend, a, a.mirror((1, -1, 0))])
    fl = minus(cyl(5, 26, 64), [cyl(7, 2.5, 24).translate((20 * math.cos(t), 20 * math.sin(t), -1))
                                for t in np.linspace(0, 2 * math.pi, 6, endpoint=False)])
    fa = fl.rotate((90, 0, 0)).translate((Rb, -leg + 4.5, 0))
    fb = fa.mirror((1, -1, 0))
    return "pipe", union([elbow(Ro, 0.0), fa, fb]) - elbow(Ri, 2.0)


def pipe_tee(rng):
    Ro, Ri, Rb, Rbi = 12.0, 10.5, 9.6, 8.4
    body = union([on_x(cyl(100, Ro, 48, center=True)), cyl(50, Rb, 48),
                  on_x(cyl(6, Ro + 3, 48, center=True)).translate((-47.5, 0, 0)),
                  on_x(cyl(6, Ro + 3, 48, center=True)).translate((47.5, 0, 0)),
                  cyl(6, Rb + 3, 48).translate((0, 0, 44.5))])
    bore = on_x(cyl(104, Ri, 48, center=True)) + cyl(54, Rbi, 48)
    return "pipe", body - bore


def knurled_knob(rng):
    R, H = 20.0, 18.0
    knob = union([cyl(H, R, 96), cyl(3, R, 96, r2=R - 3).translate((0, 0, H - 0.5)),
                  cyl(8, 8, 64).translate((0, 0, H + 2))])
    n = 30
    tooth = polygon([(R + 1.0, 0.9), (R - 1.0, 0.0), (R + 1.0, -0.9)])
    grooves = []
    for k in range(n):
        t = tooth.rotate(360 / n * k)
        grooves.append(t.extrude(H - 4, 24, 40.0).translate((0, 0, 2)))
        grooves.append(t.extrude(H - 4, 24, -40.0).translate((0, 0, 2)))
    knob = knob - Manifold.batch_boolean(grooves, OpType.Add)
    knob = minus(knob, [cyl(30, 3, 32).translate((0, 0, -1)),
                        on_x(cyl(12, 1.5, 24)).translate((0, 0, H + 6))])
    return "knob", knob


def heat_sink(rng):
    base = box(80, 60, 5)
    n = 17
    fins = []
    for k in range(n):
        x = 2 + k * (76 - 1.2) / (n - 1)
        h = 30 + round(rng.uniform(-1.5, 1.5), 2) if 0 < k < n - 1 else 30  # seeded fin heights
        fins.append(box(1.2, 60, h).translate((x, 0, 4.5)) +
                    on_y(cyl(60, 0.6, 16)).translate((x + 0.6, 0, 4.5 + h)))
    hs = union([base] + fins)
    holes = [cyl(7, 1.7, 32).translate((x, y, -1)) for x in (9.3, 70.7) for y in (8, 52)]
    holes += [cyl(2, 3.2, 32).translate((x, y, 4.0)) for x in (9.3, 70.7) for y in (8, 52)]
    groove = box(82, 4, 2).translate((-1, 28, -1))
    return "heatsink", minus(hs, holes + [groove])


def connecting_rod(rng):
    outline = CrossSection.batch_hull([circle(24, 64), circle(13, 48).translate((0, 110))])
    rod = outline.extrude(16).translate((0, 0, -8))
    pocket = CrossSection.batch_hull([circle(6, 32).translate((0, 32)),
                                      circle(3.5, 32).translate((0, 88))])
    cuts = [pocket.extrude(6).translate((0, 0, 4)), pocket.extrude(6).translate((0, 0, -10)),
            cyl(20, 16, 64, center=True), cyl(20, 7, 48, center=True).translate((0, 110, 0))]
    bosses = [on_y(cyl(14, 6, 32, center=True)).translate((s * 21, 0, 0))
              ^ box(100, 70, 16, center=True)
              for s in (-1, 1)]
    bolts = [on_y(cyl(60, 2.6, 32, center=True)).translate((s * 21, 0, 0)) for s in (-1, 1)]
    oil = on_y(cyl(30, 1.5, 24)).translate((0, 112, 0))
    return "rod", minus(union([minus(rod, cuts)] + bosses), bolts + [oil])


def valve_body(rng):
    body = Manifold.sphere(28, 64) ^ box(80, 80, 50, center=True)
    body = body + on_x(cyl(100, 16, 64, center=True))
    fl = on_x(cyl(8, 30, 64, center=True))
    body = body + fl.translate((-46, 0, 0)) + fl.translate((46, 0, 0))
    bonnet = cyl(30, 14, 64) + cyl(6, 22, 64).translate((0, 0, 20))
    body = body + bonnet
    cuts = [on_x(cyl(104, 11, 64, center=True)), cyl(60, 7, 48),
            Manifold.sphere(19, 48) ^ box(60, 60, 30, center=True)]
    for s in (-1, 1):
        for a in np.linspace(0, 2 * math.pi, 4, endpoint=False) + math.pi / 4:
            cuts.append(on_x(cyl(10, 3.2, 24, center=True))
                        .translate((s * 46, 23 * math.cos(a), 23 * math.sin(a))))
    for a in np.linspace(0, 2 * math.pi, 4, endpoint=False):
        cuts.append(cyl(8, 2.2, 24).translate((18 * math.cos(a), 18 * math.sin(a), 19)))
    return "valve", minus(body, cuts)


def wrench(rng):
    shape = union([circle(16, 64), circle(13, 64).translate((150, 0)),
                   CrossSection.batch_hull([circle(7, 32).translate((20, 0)),
                                            circle(6, 32).translate((135, 0))])])
    jaw = hexagon(17).rotate(30) + CrossSection.square((30, 17), True).translate((-16, 0))
    jaw = jaw.rotate(15)
    ring = (hexagon(13) + hexagon(13).rotate(30)).translate((150, 0))  # 12 points
    w = (shape - jaw.translate((-2, 0)) - ring).extrude(7)
    recess = CrossSection.batch_hull([circle(3.5, 32).translate((40, 0)),
                                      circle(3, 32).translate((120, 0))])
    return "tool", minus(w, [recess.extrude(2).translate((0, 0, 5.5)),
                             recess.extrude(2).translate((0, 0, -0.5))])


def bracket_l_uniform(rng):
    kind, m = bracket_l_holes(rng)
    return "remeshed", m.refine_to_length(2.5)


def housing_uniform(rng):
    kind, m = housing_box(rng)
    return "remeshed", m.refine_to_length(3.0)


def pulley_refined(rng):
    kind, m = pulley(rng)
    return "remeshed", m.refine(3)


MODELS = [
    gear_z17, gear_z30_keyway, gear_z56_web,
    bracket_l_holes, channel_u, bracket_filleted,
    plate_hole_pattern, plate_countersunk, flange_bolt_circle,
    turbine_blade, fan_rotor,
    bolt_nut_washer, bearing_set, chain_links,
    hollow_box_shell, cup, housing_box, tank_shell,
    hex_nut, stepped_shaft, pulley, i_beam, pipe_elbow, pipe_tee,
    knurled_knob, heat_sink, connecting_rod, valve_body, wrench,
    bracket_l_uniform, housing_uniform, pulley_refined,
]


# ---------------------------------------------------------------------------------------------

def write_off(path, V, F):
    with open(path, "w") as out:
        out.write(f"OFF\n{len(V)} {len(F)} 0\n")
        out.write("".join(f"{x:.17g} {y:.17g} {z:.17g}\n" for x, y, z in V))
        out.write("".join(f"3 {a} {b} {c}\n" for a, b, c in F))


def build(fn):
    """(kind, pieces, V float64 (n,3), F int64 (m,3)) for one model."""
    rng = random.Random(SEED ^ zlib.crc32(fn.__name__.encode()))
    kind, m = fn(rng)
    if m.status().name != "NoError" or m.is_empty():
        raise RuntimeError(f"{fn.__name__}: manifold status {m.status()}")
    mesh = m.to_mesh64()
    V = np.asarray(mesh.vert_properties, dtype=np.float64)[:, :3]
    F = np.asarray(mesh.tri_verts, dtype=np.int64)
    # exactly equal positions are one vertex (manifold3d's output is indexed already)
    V, inverse = np.unique(V, axis=0, return_inverse=True)
    F = inverse.reshape(-1)[F]
    return kind, len(m.decompose()), V, F


def check(V, F):
    """Problems that would make the mesh not a closed, oriented, edge-manifold one ('' if none)."""
    problems = []
    if (F[:, 0] == F[:, 1]).any() or (F[:, 1] == F[:, 2]).any() or (F[:, 2] == F[:, 0]).any():
        problems.append("repeated corner")
    d = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    ud = np.sort(d, axis=1)
    _, counts = np.unique(ud, axis=0, return_counts=True)
    if (counts != 2).any():
        problems.append(f"{int((counts != 2).sum())} edges not used twice")
    if len(np.unique(d, axis=0)) != len(d):
        problems.append("inconsistent orientation")
    elif not problems:
        # each vertex one fan of faces (no two pieces or sheets meeting at a vertex): corners at a
        # vertex joined across the edges around it must form one group per vertex
        n = len(V)
        key = F.reshape(-1) * n + F[:, [1, 2, 0]].reshape(-1)  # half-edge k: corner k to the next
        opposite = F[:, [1, 2, 0]].reshape(-1) * n + F.reshape(-1)
        order = np.argsort(key)
        twin = order[np.searchsorted(key[order], opposite)]
        # the corner at the same vertex across the edge
        other = 3 * (twin // 3) + (twin % 3 + 1) % 3
        label = np.arange(len(key))
        while True:
            new = np.minimum(label, label[other])
            new = np.minimum(new, new[new])
            np.minimum.at(new, other, new)
            if (new == label).all():
                break
            label = new
        if len(np.unique(label)) != len(np.unique(F)):
            problems.append("vertices where several fans meet")
    # zero-area (needle or cap) faces: height under a millionth of the longest edge
    area2 = np.linalg.norm(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]), axis=1)
    longest = np.max([np.linalg.norm(V[F[:, (i + 1) % 3]] - V[F[:, i]], axis=1)
                      for i in range(3)], axis=0)
    flat = area2 <= 1e-6 * longest * longest
    if flat.any():
        problems.append(f"{int(flat.sum())} zero-area faces")
    if len(np.unique(F)) != len(V):
        problems.append("unused vertices")
    return "; ".join(problems)


def cad_models(cache: pathlib.Path) -> list[tuple[str, pathlib.Path, bool]]:
    """(name, triangle OFF path, held_out) for every model, written once into `cache` (skip if
    exists)."""
    cache = pathlib.Path(cache)
    cache.mkdir(parents=True, exist_ok=True)
    out = []
    for fn in MODELS:
        name = fn.__name__
        path = cache / f"{name}.off"
        if not path.exists():
            kind, n, V, F = build(fn)
            problems = check(V, F)
            if problems:
                raise RuntimeError(f"{name}: {problems}")
            tmp = path.with_suffix(".off.tmp")
            write_off(tmp, V, F)
            tmp.replace(path)
        out.append((name, path, name in HELD_OUT))
    return out


assert len(HELD_OUT) * 4 == len(MODELS) and HELD_OUT <= {fn.__name__ for fn in MODELS}


def main():
    folder = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else
                          pathlib.Path.home() / ".cache" / "straightest-param" / "bench" / "cad")
    folder.mkdir(parents=True, exist_ok=True)
    print(f"{'name':22} {'kind':9} {'pieces':>6} {'vertices':>8} {'faces':>7} held_out")
    for fn in MODELS:
        name = fn.__name__
        kind, n, V, F = build(fn)
        problems = check(V, F)
        if problems:
            raise RuntimeError(f"{name}: {problems}")
        tmp = folder / f"{name}.off.tmp"
        write_off(tmp, V, F)
        tmp.replace(folder / f"{name}.off")
        print(f"{name:22} {kind:9} {n:6} {len(V):8} {len(F):7} {'yes' if name in HELD_OUT else ''}")


if __name__ == "__main__":
    main()
