#!/usr/bin/python3
"""Self-test of riffle_tools.vtp and tools/riffle-tools seed-figures on a small synthetic run directory whose
answers are known.

Usage: /usr/bin/python3 tests/tools/test_seed_figures.py [WORK_DIR]   (exit 0 = pass)
"""
import base64
import csv
import math
import pathlib
import struct
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
import numpy as np  # noqa: E402
from riffle_tools import seed_figures  # noqa: E402
from riffle_tools import seed_views  # noqa: E402
from riffle_tools import vtp  # noqa: E402


def array(name, values, kind, components=1):
    raw = np.ascontiguousarray(values, dtype={"Float64": "<f8", "Int32": "<i4", "UInt64": "<u8"}[kind]).tobytes()
    text = base64.b64encode(struct.pack("<I", len(raw)) + raw).decode()
    return (f'<DataArray type="{kind}" Name="{name}" NumberOfComponents="{components}" format="binary">\n'
            f"{text}\n</DataArray>\n")


def write_vtp(path, points, data):
    n = len(points)
    body = "".join(array(name, values, kind, 3 if np.ndim(values) == 2 else 1) for name, (values, kind) in data.items())
    path.write_text('<?xml version="1.0"?>\n<VTKFile type="PolyData" version="1.0" byte_order="LittleEndian" '
                    'header_type="UInt32">\n<PolyData>\n'
                    f'<Piece NumberOfPoints="{n}" NumberOfVerts="{n}" NumberOfLines="0" NumberOfStrips="0" '
                    f'NumberOfPolys="0">\n<PointData>\n{body}</PointData>\n<Points>\n'
                    + array("Points", points, "Float64", 3) + "</Points>\n</Piece>\n</PolyData>\n</VTKFile>\n")


def write_pvd(path, entries):
    path.write_text('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n<Collection>\n'
                    + "\n".join(entries) + "\n</Collection>\n</VTKFile>\n")


def check_pieces(work):
    """A frame written in pieces over MPI ranks (.pvtp naming one .vtp per rank) reads as the whole frame: the pieces
    joined and ordered by id, as a gathered frame is; a subset of fields keeps the id order; a piece with other
    arrays is refused."""
    vtk = work / "pieces" / "vtk"
    vtk.mkdir(parents=True, exist_ok=True)
    points = np.array([[0.0, 0.0, float(k)] for k in range(5)])
    radius = np.array([1.0, 2.0, 3.0, 4.0, 5.0])
    # rank 0 holds ids 3 and 1, rank 1 ids 4, 0 and 2
    for rank, ids in ((0, [3, 1]), (1, [4, 0, 2])):
        write_vtp(vtk / f"solids_000007_{rank}.vtp", points[ids],
                  {"id": (np.array(ids), "UInt64"), "radius": (radius[ids], "Float64")})
    (vtk / "solids_000007.pvtp").write_text(
        '<?xml version="1.0"?>\n<VTKFile type="PPolyData" version="1.0" byte_order="LittleEndian" '
        'header_type="UInt32">\n  <PPolyData GhostLevel="0">\n    <PPointData Scalars="radius">\n'
        '      <PDataArray type="UInt64" Name="id" NumberOfComponents="1"/>\n'
        '      <PDataArray type="Float64" Name="radius" NumberOfComponents="1"/>\n    </PPointData>\n'
        '    <PPoints>\n      <PDataArray type="Float64" Name="Points" NumberOfComponents="3"/>\n    </PPoints>\n'
        '    <Piece Source="solids_000007_0.vtp"/>\n    <Piece Source="solids_000007_1.vtp"/>\n'
        '  </PPolyData>\n</VTKFile>\n')
    frame = vtp.read_vtp(vtk / "solids_000007.pvtp")
    assert frame["id"].tolist() == [0, 1, 2, 3, 4], frame["id"]
    assert np.array_equal(frame["radius"], radius) and np.array_equal(frame["points"], points)
    only = vtp.read_vtp(vtk / "solids_000007.pvtp", ["radius"])
    assert sorted(only) == ["points", "radius"] and np.array_equal(only["radius"], radius), only
    write_vtp(vtk / "solids_000007_1.vtp", points[[4, 0, 2]], {"id": (np.array([4, 0, 2]), "UInt64")})
    try:
        vtp.read_vtp(vtk / "solids_000007.pvtp")
    except vtp.VtpError as error:
        assert "other arrays" in str(error), error
    else:
        raise AssertionError("a piece without the radius was read")


def write_appended_vtp(path, points, data, point_type="Float32"):
    """A frame as riffle writes it by default: every array's bytes raw after the XML, at its offset."""
    types = {"Float32": "<f4", "Float64": "<f8", "Int32": "<i4", "UInt64": "<u8"}
    block = bytearray()
    elements = []
    for name, (values, kind) in list(data.items()) + [("Points", (points, point_type))]:
        raw = np.ascontiguousarray(values, dtype=types[kind]).tobytes()
        components = 3 if np.ndim(values) == 2 else 1
        elements.append(f'<DataArray type="{kind}" Name="{name}" NumberOfComponents="{components}" '
                        f'format="appended" offset="{len(block)}"/>\n')
        block += struct.pack("<I", len(raw)) + raw
    n = len(points)
    head = ('<?xml version="1.0"?>\n<VTKFile type="PolyData" version="1.0" byte_order="LittleEndian" '
            'header_type="UInt32">\n<PolyData>\n'
            f'<Piece NumberOfPoints="{n}" NumberOfVerts="0" NumberOfLines="0" NumberOfStrips="0" '
            f'NumberOfPolys="0">\n<PointData>\n{"".join(elements[:-1])}</PointData>\n<Points>\n{elements[-1]}'
            '</Points>\n</Piece>\n</PolyData>\n  <AppendedData encoding="raw">\n   _')
    path.write_bytes(head.encode() + bytes(block) + b"\n  </AppendedData>\n</VTKFile>\n")


def check_appended(work):
    """A frame with its arrays raw after the XML (riffle's default) reads as the same frame written inline: the
    single-precision arrays as their float values, in double; bytes that spell "<" or "_" in the block do not
    confuse it; an offset past the block is refused, naming the array."""
    vtk = work / "appended"
    vtk.mkdir(parents=True, exist_ok=True)
    points = np.array([[0.1, 0.2, 0.3], [1.0 / 3.0, 60.0, 0.0078125], [-2.5, 1e-7, 4.0]])
    velocity = np.array([[1.0, 2.0, 3.0], [0.1, 0.2, 0.3], [5.0, 6.0, 7.0]])
    ids = np.array([7, ord("<") * 256 + ord("_"), 2 ** 40])  # an id whose bytes hold '<' and '_'
    data = {"id": (ids, "UInt64"), "velocity": (velocity, "Float32"), "pressure": (np.array([1.5, 2.5, 1e5]), "Float64"),
            "kind": (np.array([0, 1, 2], dtype=np.int32), "Int32")}
    write_appended_vtp(vtk / "a.vtp", points, data)
    frame = vtp.read_vtp(vtk / "a.vtp")
    assert frame["points"].dtype == np.float64 and frame["velocity"].dtype == np.float64
    assert np.array_equal(frame["points"], points.astype(np.float32).astype(np.float64)), frame["points"]
    assert np.array_equal(frame["velocity"], velocity.astype(np.float32).astype(np.float64))
    assert np.array_equal(frame["pressure"], [1.5, 2.5, 1e5]) and frame["id"].tolist() == ids.tolist()
    assert frame["kind"].tolist() == [0, 1, 2]
    only = vtp.read_vtp(vtk / "a.vtp", ["pressure"])
    assert sorted(only) == ["points", "pressure"], only
    broken = (vtk / "a.vtp").read_bytes().replace(b'offset="0"', b'offset="9999"', 1)
    (vtk / "broken.vtp").write_bytes(broken)
    try:
        vtp.read_vtp(vtk / "broken.vtp")
    except vtp.VtpError as error:
        assert "array id" in str(error) and "offset 9999" in str(error), error
    else:
        raise AssertionError("an offset past the appended block was read")


def check_velocity_gradient():
    """The least-squares gradient is exact for linear velocity fields, whatever the neighbours' arrangement: on a
    jittered lattice block (free faces and corners included) a simple shear u = (a z, 0, 0) has |S|^2 = a^2/2 and
    Q = 0, a rigid rotation about z at w has |S|^2 = 0 and Q = w^2 (seed Eqs. 29-30, Frobenius norms)."""
    rng = np.random.default_rng(7)
    l0 = 0.01
    grid = np.stack(np.meshgrid(*(np.arange(6) * l0,) * 3, indexing="ij"), -1).reshape(-1, 3)
    points = grid + rng.uniform(-0.2, 0.2, grid.shape) * l0
    a, w = 3.0, 2.0
    shear = np.column_stack([a * points[:, 2], np.zeros(len(points)), np.zeros(len(points))])
    rotation = np.column_stack([-w * points[:, 1], w * points[:, 0], np.zeros(len(points))])
    for velocity, s2_expected, q_expected in ((shear, a * a / 2, 0.0), (rotation, 0.0, w * w)):
        G, valid = seed_views.velocity_gradient(points, velocity + 0.37, 2.1 * l0)  # a uniform part changes nothing
        assert valid.all(), np.where(~valid)
        s2, q = seed_views.strain_and_q(G)
        assert np.allclose(s2, s2_expected, rtol=0, atol=1e-9 * max(a * a, w * w)), (s2.min(), s2.max())
        assert np.allclose(q, q_expected, rtol=0, atol=1e-9 * max(a * a, w * w)), (q.min(), q.max())
    # neighbour_pairs agrees with the brute-force count
    i, j = seed_views.neighbour_pairs(points, 2.1 * l0)
    distance = np.linalg.norm(points[:, None] - points[None], axis=2)
    assert len(i) == int(np.sum(distance < 2.1 * l0)) - len(points)
    assert np.all(np.linalg.norm(points[i] - points[j], axis=1) < 2.1 * l0)


# The views' bed: a plane of large grains (R = 7.5 mm) touching on a 15 mm lattice, centres at z = 37.5 mm (16 x 10,
# over y 0-150 mm), and below every large grain of rows 3-9 (y >= 52.5 mm) a small grain (r = 2.5 mm) at z = 7.5 mm.
LARGE, SMALL = 0.0075, 0.0025


def views_bed():
    x = 0.0075 + 0.015 * np.arange(16)
    y = 0.0075 + 0.015 * np.arange(10)
    large = np.array([[a, b, 0.0375] for b in y for a in x])
    small = np.array([[a, b, 0.0075] for b in y[3:] for a in x])
    points = np.vstack([large, small])
    radius = np.array([LARGE] * len(large) + [SMALL] * len(small))
    size_class = np.array([2] * len(large) + [0] * len(small), dtype=np.int32)
    # velocities relative to the tank: front-row large grains 0.1 m/s, the other large 0.3, small -0.05
    relative = np.where(size_class == 2, np.where(points[:, 1] < 0.015, 0.1, 0.3), -0.05)
    return points, radius, size_class, relative


def write_views_run(run, f, amplitude, shear):
    """One period, frames at every eighth (every phase hit exactly), the bed above fixed in the tank, and MPS fluid
    on a 10 mm lattice jittered in x and y, moving with the tank plus the shear u = (shear z, 0, 0)."""
    (run / "vtk").mkdir(parents=True, exist_ok=True)
    scene = run / "scene.toml"
    scene.write_text('[tank]\nsize = [0.24, 0.16, 0.20]\n[tank.motion]\nkind = "sinusoidal"\n'
                     f"direction = [1.0, 0.0, 0.0]\namplitude = {amplitude}\nfrequency = {f}\nramp_time = 0.0\n"
                     "[fluid]\nspacing = 0.01\n")
    points, radius, size_class, relative = views_bed()
    rng = np.random.default_rng(3)
    lattice = np.stack(np.meshgrid(0.005 + 0.01 * np.arange(24), 0.005 + 0.01 * np.arange(16),
                                   0.005 + 0.01 * np.arange(6), indexing="ij"), -1).reshape(-1, 3)
    lattice[:, :2] += rng.uniform(-0.001, 0.001, (len(lattice), 2))
    solids, fluid = [], []
    for k in range(9):
        t = k / (8 * f)
        shift = np.array([-amplitude * math.sin(2 * math.pi * f * t), 0, 0])
        v_tank = -amplitude * 2 * math.pi * f * math.cos(2 * math.pi * f * t)
        velocity = np.zeros((len(points), 3))
        velocity[:, 0] = relative + v_tank
        write_vtp(run / "vtk" / f"solids_{k:06d}.vtp", points + shift, {
            "velocity": (velocity, "Float64"), "radius": (radius, "Float64"), "size_class": (size_class, "Int32")})
        flow = np.zeros((len(lattice), 3))
        flow[:, 0] = v_tank + shear * lattice[:, 2]
        write_vtp(run / "vtk" / f"fluid_{k:06d}.vtp", lattice + shift, {
            "kind": (np.zeros(len(lattice), dtype=np.int32), "Int32"), "velocity": (flow, "Float64")})
        solids.append(f'<DataSet timestep="{t!r}" group="" part="0" file="vtk/solids_{k:06d}.vtp"/>')
        fluid.append(f'<DataSet timestep="{t!r}" group="" part="0" file="vtk/fluid_{k:06d}.vtp"/>')
    write_pvd(run / "solids.pvd", solids)
    write_pvd(run / "fluid.pvd", fluid)
    return scene, lattice


def pixel_bound(perimeter, area):
    """The largest error of a pixel count of discs as an area fraction: a pixel is misjudged only if a disc's edge
    crosses it, i.e. it lies within half a diagonal (p / sqrt 2) of the edge, a band of area <= perimeter * sqrt 2 p,
    and each misjudged pixel is wrong by at most its whole area."""
    return perimeter * math.sqrt(2) * seed_figures.PIXEL / area


def check_views(work):
    run = work / "views"
    f, amplitude, shear = 1.7, 0.01, 5.0
    scene, lattice = write_views_run(run, f, amplitude, shear)
    out = work / "views_figures"
    code = seed_figures.main([str(run), "--scene", str(scene), "--out", str(out), "--stages", "1", "--times", "0.5",
                              "--conc-times", "0.5", "--figures", "fig04", "fig07_08", "fig09", "fig10", "fig13",
                              "fig16"])
    assert code == 0, code

    def rows(name):
        with open(out / name, newline="") as handle:
            return list(csv.DictReader(handle))

    length, width = 0.24, 0.16
    # Fig. 4: from above only the large grains show; the small ones lie under them (an exact zero). The large ones
    # cover 160 discs' area of the tank's plan.
    top = {int(r["size_class"]): r for r in rows("fig04_top_views.csv")}
    assert float(top[0]["area_fraction"]) == 0.0 and int(top[0]["grains_seen"]) == 0, top[0]
    assert int(top[2]["grains_seen"]) == 160, top[2]
    expected = 160 * math.pi * LARGE ** 2 / (length * width)
    bound = pixel_bound(160 * 2 * math.pi * LARGE, length * width)
    assert abs(float(top[2]["area_fraction"]) - expected) <= bound, (top[2], expected, bound)
    # Figs. 7-8: through the front wall, the 30-45 mm strip shows a row of touching discs (pi/4 of it), nothing
    # else; the 0-15 mm strip shows the 16 small discs (through the water, at any depth); the others are empty.
    occupancy = {(int(r["size_class"]), int(r["sublayer"])): float(r["occupancy_rate"])
                 for r in rows("fig07_08_occupancy.csv")}
    strip = length * seed_figures.SUBLAYER
    assert abs(occupancy[(2, 2)] - math.pi / 4) <= pixel_bound(16 * 2 * math.pi * LARGE, strip), occupancy
    assert abs(occupancy[(0, 0)] - 16 * math.pi * SMALL ** 2 / strip) <= pixel_bound(16 * 2 * math.pi * SMALL, strip)
    assert all(v == 0.0 for (k, layer), v in occupancy.items() if (k, layer) not in ((2, 2), (0, 0))), occupancy
    # Fig. 9: within 15 mm of the front wall only the front row of large grains shows (0.1 m/s relative to the
    # tank, at every phase); the small grains (rows from y = 52.5 mm) are deeper than that: no pixel. All grains:
    # 16 at 0.1 and 144 at 0.3 in the 30-45 mm sub-layer, the small ones at -0.05 in 0-15 mm.
    profile = rows("fig09_side_view_velocity.csv")
    assert len({r["phase_index"] for r in profile}) == 4
    for row in profile:
        layer = int(row["sublayer"])
        assert int(row["frames"]) >= 1 and float(row["mean_abs_phase_error_deg"]) < 1e-6, row
        if layer == 2:
            assert abs(float(row["mean_vx_seen_tank_m_s"]) - 0.1) < 1e-9, row
            assert abs(float(row["mean_vx_all_grains_tank_m_s"]) - (16 * 0.1 + 144 * 0.3) / 160) < 1e-9, row
        else:
            assert int(row["seen_pixels"]) == 0, row
        if layer == 0:
            assert abs(float(row["mean_vx_all_grains_tank_m_s"]) + 0.05) < 1e-9, row
    # Fig. 10: the 15 mm slab at y = 80 mm holds the lattice planes y = 75 and 85 mm (x-y jitter 1 mm) and the grain
    # row at y = 82.5 mm; the fluid's x-velocity relative to the tank is the shear, its z-velocity zero.
    slab = rows("fig10_fluid_slab.csv")
    for p in range(4):
        panel = [r for r in slab if int(r["phase_index"]) == p]
        water = [r for r in panel if r["particle"] == "fluid"]
        assert len(water) == 2 * 24 * 6, len(water)
        assert all(abs(float(r["vx_tank_m_s"]) - shear * float(r["z_m"])) < 1e-9 and float(r["vz_m_s"]) == 0
                   for r in water)
        grains = [int(r["size_class"]) for r in panel if r["particle"] == "grain"]
        assert sorted(grains) == [0] * 16 + [2] * 16, grains
    # Fig. 13: the fluid within l0 of the plane averaged on 10 mm cells: each cell's velocity is the shear at its
    # mid-height (the lattice's z is not jittered), green (>= 0.2 m/s) from the 40-50 mm cells up (0.225 m/s).
    cells = rows("fig13_cross_section.csv")
    assert len(cells) == 4 * 24 * 6, len(cells)
    for row in cells:
        speed = shear * float(row["cell_z_m"])
        assert abs(float(row["mean_vx_tank_m_s"]) - speed) < 1e-9 and int(row["samples"]) == 2, row
        assert int(row["highlighted"]) == (speed >= 0.2), row
    # Fig. 16: the least-squares gradient of the shear everywhere (free faces too): |S|^2 = a^2/2, Q = 0.
    strain = rows("fig16_strain_q.csv")
    assert len(strain) == 6 and sum(int(r["particles"]) for r in strain) == len(lattice), strain
    for row in strain:
        assert abs(float(row["mean_S2_1_s2"]) - shear ** 2 / 2) < 1e-9 * shear ** 2, row
        assert abs(float(row["mean_Q_1_s2"])) < 1e-9 * shear ** 2, row
    for name in ("fig04_top_views.png", "fig07_08_occupancy.png", "fig09_side_view_velocity.png",
                 "fig10_fluid_slab.png", "fig13_cross_section.png", "fig16_strain_q.png"):
        assert (out / name).stat().st_size > 1000, name
    # A time beyond the run: the figure is skipped (no PNG), the run still succeeds.
    beyond = work / "views_beyond"
    assert seed_figures.main([str(run), "--scene", str(scene), "--out", str(beyond), "--times", "85",
                              "--figures", "fig04"]) == 0
    assert not (beyond / "fig04_top_views.png").exists()


def main():
    work = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else tempfile.mkdtemp(prefix="seed_figures_"))
    run = work / "run"
    (run / "vtk").mkdir(parents=True, exist_ok=True)
    f, amplitude = 1.7, 0.01
    scene = run / "scene.toml"
    scene.write_text('[tank]\nsize = [0.24, 0.16, 0.20]\n[tank.motion]\nkind = "sinusoidal"\n'
                     f"direction = [1.0, 0.0, 0.0]\namplitude = {amplitude}\nfrequency = {f}\nramp_time = 0.0\n")
    # One small grain at 10 mm, two medium at 20 mm, one large at 50 mm; all move with velocity u(t) = 0.1 m/s + tank
    radius = np.array([0.0025, 0.005, 0.005, 0.0075])
    size_class = np.array([0, 1, 1, 2], dtype=np.int32)
    points = np.array([[0.05, 0.05, 0.010], [0.10, 0.05, 0.020], [0.15, 0.05, 0.020], [0.2, 0.05, 0.050]])
    period = 1.0 / f
    times = [k * period / 8 for k in range(17)]  # two periods, frames at every eighth
    solids_pvd, fluid_pvd = [], []
    for k, t in enumerate(times):
        shift = np.array([-amplitude * math.sin(2 * math.pi * f * t), 0, 0])
        v_tank = -amplitude * 2 * math.pi * f * math.cos(2 * math.pi * f * t)
        velocity = np.tile([0.1 + v_tank, 0.0, 0.0], (4, 1))
        velocity[1, 2] = 0.3  # one medium grain moves up: T_g of layer 4 (20-25 mm) = (1/3)(0.15^2) per grain
        velocity[2, 2] = 0.0
        mass = 1318.0 * 4 / 3 * math.pi * radius ** 3
        force = np.zeros((4, 3))
        force[:, 2] = mass * 9.81  # balanced
        # The small grain drifts +10 mm along x over the two periods (in the tank's frame): the drift analysis
        # must find it; nothing else depends on x.
        drifted = points.copy()
        drifted[0, 0] += 0.01 * k / 16
        write_vtp(run / "vtk" / f"solids_{k:06d}.vtp", drifted + shift, {
            "id": (np.arange(4), "UInt64"), "velocity": (velocity, "Float64"), "radius": (radius, "Float64"),
            "mass": (mass, "Float64"), "force": (force, "Float64"), "contact_force": (force * 0.25, "Float64"),
            "drag_force": (np.zeros((4, 3)), "Float64"), "pressure_force": (force * 0.75, "Float64"),
            "size_class": (size_class, "Int32")})
        fluid_points = np.array([[0.1, 0.08, 0.0025], [0.1, 0.08, 0.0475], [0.0, 0.0, 0.0]]) + shift
        fluid_velocity = np.array([[v_tank, 0, 0], [v_tank - 0.2, 0, 0], [v_tank, 0, 0]])
        write_vtp(run / "vtk" / f"fluid_{k:06d}.vtp", fluid_points, {
            "kind": (np.array([0, 0, 1], dtype=np.int32), "Int32"), "velocity": (fluid_velocity, "Float64")})
        solids_pvd.append(f'<DataSet timestep="{t!r}" group="" part="0" file="vtk/solids_{k:06d}.vtp"/>')
        fluid_pvd.append(f'<DataSet timestep="{t!r}" group="" part="0" file="vtk/fluid_{k:06d}.vtp"/>')
    for name, entries in (("solids.pvd", solids_pvd), ("fluid.pvd", fluid_pvd)):
        (run / name).write_text('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n<Collection>\n'
                                + "\n".join(entries) + "\n</Collection>\n</VTKFile>\n")

    frame = vtp.read_vtp(run / "vtk" / "solids_000000.vtp")
    assert np.allclose(frame["points"], points) and frame["size_class"].tolist() == [0, 1, 1, 2]  # k = 0: no drift
    assert frame["id"].dtype == np.uint64 and frame["velocity"].shape == (4, 3)

    code = seed_figures.main([str(run), "--scene", str(scene), "--stages", "2", "--conc-times", "0", "1",
                               "--drift-windows", "0-2"])
    assert code == 0, code
    out = run / "figures"

    def rows(name):
        with open(out / name, newline="") as handle:
            return list(csv.DictReader(handle))

    area = 0.24 * 0.16 * 0.015
    for row in rows("fig11_concentration.csv"):
        k, layer = int(row["size_class"]), int(row["sublayer"])
        expected = {(0, 0): radius[0] ** 3, (1, 1): 2 * radius[1] ** 3, (2, 3): radius[3] ** 3}.get((k, layer), 0)
        assert math.isclose(float(row["volume_concentration"]), 4 / 3 * math.pi * expected / area, rel_tol=1e-6,
                            abs_tol=1e-12), row
    speeds = rows("fig14_velocity_phases.csv")
    assert len({r["phase_index"] for r in speeds}) == 4
    for row in speeds:
        assert abs(float(row["mean_vx_relative_to_tank_m_s"]) - 0.1) < 1e-9, row
        assert float(row["mean_abs_phase_error_deg"]) < 1e-6, row
    fluid = {int(r["sublayer"]): float(r["mean_vx_relative_to_tank_m_s"]) for r in rows("fig15_fluid_velocity.csv")}
    assert set(fluid) == {0, 9} and all(abs(fluid[k] - v) < 1e-9 for k, v in {0: 0.0, 9: -0.2}.items()), fluid
    temperature = rows("fig20_granular_temperature.csv")
    assert abs(float(temperature[3]["Tg_class_1_m2_s2"]) - 0.15 ** 2 / 3) < 1e-12, temperature[3]
    assert abs(float(temperature[3]["Tg_class_0_m2_s2"])) < 1e-12
    forces = rows("fig17_19_force_balance.csv")
    for row in forces:
        assert abs(float(row["total_z_over_m_g"])) < 1e-9 and abs(float(row["pressure_force_z_over_m_g"]) - 0.75) < 1e-9
    # Fig. 19: pressure 0.75 m g and contact 0.25 m g upward on every grain, no drag, at all four phases; the
    # small grain (10 mm) is in sub-layer 2, the medium ones (20 mm) in 4, the large one (50 mm) in 10.
    profiles = rows("fig19_z_force_profiles.csv")
    assert len({r["phase_index"] for r in profiles}) == 4, profiles
    assert {(int(r["size_class"]), int(r["sublayer"])) for r in profiles} == {(0, 2), (1, 4), (2, 10)}, profiles
    for row in profiles:
        assert abs(float(row["pressure_force_z_over_m_g"]) - 0.75) < 1e-9, row
        assert abs(float(row["contact_force_z_over_m_g"]) - 0.25) < 1e-9, row
        assert abs(float(row["drag_force_z_over_m_g"])) < 1e-12 and abs(float(row["total_z_over_m_g"]) - 1) < 1e-9
    assert int([r for r in profiles if r["size_class"] == "1"][0]["samples"]) == 2 * int(profiles[0]["frames"])
    # Drift over t/T 0-2: the small grain (x = 50 mm: column 2 of ten 24 mm columns, z = 10 mm: layer 0) moved
    # +10 mm in x; the large one (x = 200 mm, z = 50 mm: column 8, layer 3) did not move.
    moved = {(r["group"], int(r["column"]), int(r["layer"])): (float(r["mean_dx_m"]), float(r["mean_dz_m"]))
             for r in rows("drift.csv")}
    assert np.allclose(moved[("0", 2, 0)], (0.01, 0.0), atol=1e-12) and moved[("all", 2, 0)] == moved[("0", 2, 0)]
    assert np.allclose(moved[("2", 8, 3)], (0.0, 0.0), atol=1e-12), moved
    assert len([key for key in moved if key[0] == "all"]) == 4  # one cell per grain
    # The grains never move vertically here: no segregation. A bed of height 60 mm in three layers of volumes
    # 1 : 2 : 1 (centroids 7.5, 30, 52.5 mm) is fully sorted from a mixed start (all at 30 mm): index 1.
    assert all(abs(float(row["segregation_index"])) < 1e-12 for row in rows("fig06_centroids.csv"))
    assert math.isclose(seed_figures.segregation_index([1, 2, 1], [0.03, 0.03, 0.03], [0.0075, 0.03, 0.0525]), 1.0)
    assert math.isclose(seed_figures.segregation_index([1, 2, 1], [0.03, 0.03, 0.03], [0.01875, 0.03, 0.04125]), 0.5)
    for name in ("fig03_snapshot_tT0.png", "fig06_centroids.png", "fig11_concentration.png", "fig14_velocity_phases.png",
                 "fig15_fluid_velocity.png", "fig17_19_force_balance.png", "fig19_z_force_profiles.png", "fig20_granular_temperature.png", "drift.png"):
        assert (out / name).stat().st_size > 1000, name
    check_velocity_gradient()
    check_pieces(work)
    check_appended(work)
    check_views(work)
    print(f"test_seed_figures: passed ({work})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
