#!/usr/bin/env python3
"""Our mesh readers (cli/mesh_io) against vcglib's importers (what MeshLab reads with), measured:

  speed     the 1.65M-vertex mesh (face.off, 3 midpoint subdivisions) as OFF, OBJ, binary PLY,
            binary and ASCII STL and binary PLY tristrips: best of 3 reads with each, in one
            process (sdp_reader_bench time; vcglib's STL welded and its tristrips' degenerate
            joins dropped, as MeshLab's loader does)
  bad input damaged copies of nefertiti in each format (truncations, byte flips, huge counts,
            out-of-range and negative indices, nan/inf coordinates; a fixed seed, so every run
            tries the same files) plus the bad-input meshes of resources/meshes/invalid: each file
            read once by each reader in its own process (sdp_reader_bench read), classified as
            refused, accepted (a valid mesh), non-finite (a nan/inf coordinate reached the mesh,
            which the core refuses), bad index (a face index out of range reached the mesh),
            crashed (a signal) or hung (over 10 s)

  png       the checkerboard PNG written by ours and by libpng (sdp_png_bench), when libpng is there

Writes bench/results/readers.md and, with --doc, that file's bench:readers block.
  .venv/bin/python bench/readers.py --build build [--doc docs/benchmarks.md]"""
import argparse
import collections
import importlib.util
import pathlib
import random
import re
import struct
import subprocess
import sys

import numpy as np

REPO = pathlib.Path(__file__).resolve().parents[1]
RESULTS = REPO / "bench" / "results"
CACHE = pathlib.Path.home() / ".cache" / "straightest-param" / "bench" / "readers"
SEED_MESH = REPO / "resources" / "meshes" / "disk" / "nefertiti.off"
CLASSES = ["refused", "accepted", "non-finite", "bad index", "crashed", "hung"]


def read_off(path):
    tokens = pathlib.Path(path).read_text().split()
    nv, nf = int(tokens[1]), int(tokens[2])
    V = np.array(tokens[4:4 + 3 * nv], dtype=float).reshape(nv, 3)
    rest = np.array(tokens[4 + 3 * nv:4 + 3 * nv + 4 * nf], dtype=np.int64).reshape(nf, 4)
    return V, rest[:, 1:]


def input_meshes():
    """scripts/make-input-meshes.py as a module: its STL writers and tristrip maker."""
    spec = importlib.util.spec_from_file_location("make_input_meshes",
                                                  REPO / "scripts" / "make-input-meshes.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def write_formats(V, F, stem, reuse=False):
    """stem.off, stem.obj (ascii), stem.ply (binary little-endian), and, as scanners and CAD
    tools write them, stem_binary.stl, stem_ascii.stl and stem_strips.ply (tristrips). With
    `reuse`, files a run already wrote (same mesh, same writers) are kept."""
    names = {"off": ".off", "obj": ".obj", "ply": ".ply", "stl": "_binary.stl",
             "stl ascii": "_ascii.stl", "ply tristrips": "_strips.ply"}
    kept = {fmt: stem.with_name(stem.name + suffix) for fmt, suffix in names.items()}
    if reuse and all(path.exists() for path in kept.values()):
        return kept
    paths = {}
    off = stem.with_suffix(".off")
    with open(off, "w") as f:
        f.write(f"OFF\n{len(V)} {len(F)} 0\n")
        np.savetxt(f, V, fmt="%.17g")
        np.savetxt(f, np.hstack([np.full((len(F), 1), 3), F]), fmt="%d")
    paths["off"] = off
    obj = stem.with_suffix(".obj")
    with open(obj, "w") as f:
        np.savetxt(f, V, fmt="v %.17g %.17g %.17g")
        np.savetxt(f, F + 1, fmt="f %d %d %d")
    paths["obj"] = obj
    ply = stem.with_suffix(".ply")
    with open(ply, "wb") as f:
        f.write((f"ply\nformat binary_little_endian 1.0\nelement vertex {len(V)}\n"
                 "property double x\nproperty double y\nproperty double z\n"
                 f"element face {len(F)}\nproperty list uchar int vertex_indices\n"
                 "end_header\n").encode())
        f.write(V.astype("<f8").tobytes())
        faces = np.zeros(len(F), dtype=[("n", "u1"), ("i", "<i4", (3,))])
        faces["n"] = 3
        faces["i"] = F
        f.write(faces.tobytes())
    paths["ply"] = ply
    maker = input_meshes()
    Vl, Fl = [tuple(v) for v in V.tolist()], F.tolist()
    paths["stl"] = stem.with_name(stem.name + "_binary.stl")
    maker.write_stl_binary(paths["stl"], Vl, Fl)
    paths["stl ascii"] = stem.with_name(stem.name + "_ascii.stl")
    maker.write_stl_ascii(paths["stl ascii"], Vl, Fl, stem.name)
    paths["ply tristrips"] = stem.with_name(stem.name + "_strips.ply")
    maker.write_ply_tristrips(paths["ply tristrips"], Vl, Fl)
    return paths


def damaged(paths, folder, rng):
    """(format, name, bytes) of damaged copies of each file."""
    cases = []
    for fmt, path in paths.items():
        data = path.read_bytes()
        header_end = data.find(b"end_header\n") + 11 if fmt.startswith("ply") else 0
        for k in range(12):  # truncations
            cut = rng.randrange(1, len(data))
            cases.append((fmt, f"truncated{k}", data[:cut]))
        for k in range(40):  # byte flips
            b = bytearray(data)
            for _ in range(rng.randint(1, 8)):
                b[rng.randrange(len(b))] = rng.randrange(256)
            cases.append((fmt, f"flipped{k}", bytes(b)))
        if fmt == "stl":
            for k, count in enumerate([2 ** 32 - 1, 561, 600]):  # the triangle count
                b = bytearray(data)
                b[80:84] = struct.pack("<I", count)
                cases.append((fmt, f"count{k}", bytes(b)))
            for k, value in enumerate([float("nan"), float("inf")]):
                b = bytearray(data)
                b[84 + 12:84 + 16] = struct.pack("<f", value)
                cases.append((fmt, f"coordinate{k}", bytes(b)))
        elif fmt == "stl ascii":
            text = data.decode()
            for k, (old, new) in enumerate([("endfacet", "endfct"), ("outer loop", "outer"),
                                            ("vertex ", "vertex nan "), ("vertex ", "vertex 1e999 "),
                                            ("endloop", "vertex 0 0 0\nendloop")]):
                cases.append((fmt, f"edit{k}", text.replace(old, new, 1).encode()))
        elif fmt == "ply tristrips":
            body = bytearray(data)
            offset = header_end + 299 * 12 + 4  # the strip's first index
            for k, index in enumerate([299, -2, 2 ** 31 - 1]):
                b = bytearray(body)
                b[offset:offset + 4] = struct.pack("<i", index)
                cases.append((fmt, f"index{k}", bytes(b)))
            b = bytearray(body)
            b[offset - 4:offset] = struct.pack("<i", 2 ** 31 - 1)  # the strip's length
            cases.append((fmt, "length", bytes(b)))
        elif fmt == "ply":
            text = data[:header_end].decode()
            for k, (old, new) in enumerate([("element vertex 299", "element vertex 2000000000"),
                                            ("element face", "element face 4000000000 #"),
                                            ("uchar int", "uint int"), ("double x", "float x"),
                                            ("binary_little_endian", "binary_big_endian"),
                                            ("binary_little_endian", "ascii")]):
                cases.append((fmt, f"header{k}", text.replace(old, new, 1).encode() +
                              data[header_end:]))
            body = bytearray(data)
            offset = header_end + 299 * 24  # the first face
            for k, index in enumerate([299, -1, 2 ** 31 - 1]):
                b = bytearray(body)
                b[offset + 1:offset + 5] = struct.pack("<i", index)
                cases.append((fmt, f"index{k}", bytes(b)))
            for k, value in enumerate([float("nan"), float("inf")]):
                b = bytearray(body)
                b[header_end:header_end + 8] = struct.pack("<d", value)
                cases.append((fmt, f"coordinate{k}", bytes(b)))
        else:
            text = data.decode()
            lines = text.splitlines()
            edits = []
            if fmt == "off":
                edits = [(1, "299 562 0", "2000000000 562 0"), (1, "299 562 0", "299 4000000000 0"),
                         (1, "299 562 0", "-5 562 0")]
                face_line, vertex_line = 2 + 299, 2
                edits += [(face_line, None, "3 0 1 299"), (face_line, None, "3 0 1 -1"),
                          (face_line, None, "3 0 1 99999999999"), (face_line, None, "200 0 1 2"),
                          (vertex_line, None, "nan 0 0"), (vertex_line, None, "1e999 0 0")]
            else:
                face_line = next(i for i, l in enumerate(lines) if l.startswith("f "))
                edits = [(face_line, None, "f 1 2 300"), (face_line, None, "f 1 2 0"),
                         (face_line, None, "f 1 2 -400"), (face_line, None, "f 1 2 99999999999"),
                         (face_line, None, "f 1/2/3/4 2 3"), (0, None, "v nan 0 0"),
                         (0, None, "v 1e999 0 0")]
            for k, (line, old, new) in enumerate(edits):
                copy = list(lines)
                copy[line] = copy[line].replace(old, new) if old else new
                cases.append((fmt, f"edit{k}", ("\n".join(copy) + "\n").encode()))
        cases.append((fmt, "empty", b""))
        cases.append((fmt, "garbage", bytes(rng.randrange(256) for _ in range(2048))))
    return cases


def classify(binary, reader, path):
    try:
        done = subprocess.run([str(binary), "read", reader, str(path)], capture_output=True,
                              text=True, errors="replace", timeout=10)
    except subprocess.TimeoutExpired:
        return "hung", ""
    if done.returncode < 0 or done.returncode > 1:
        return "crashed", f"(exit {done.returncode})"
    first = (done.stdout.strip().splitlines() or ["crashed"])[0]
    kind = first.split(" ", 1)[0]
    if kind == "accepted-invalid":
        return ("non-finite" if "not finite" in first else "bad index"), ""
    return (kind if kind in CLASSES else "crashed"), ""


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--build", default=str(REPO / "build"))
    parser.add_argument("--doc", help="the file holding the bench:readers block "
                                          "(docs/benchmarks.md)")
    args = parser.parse_args()
    bin_dir = pathlib.Path(args.build) / "bin"
    reader_bench = bin_dir / "sdp_reader_bench"
    if not reader_bench.exists():
        sys.exit("readers.py: build sdp_reader_bench first (needs the MeshLab 2025.07 sources)")
    CACHE.mkdir(parents=True, exist_ok=True)
    work = CACHE / "work"
    work.mkdir(exist_ok=True)

    # Speed on the 1.65M-vertex mesh.
    face = REPO.parent / "shared" / "meshes" / "disk" / "face.off"
    big = CACHE / "face_s3.off"
    if not big.exists():
        subprocess.run([bin_dir / "sdp_bench", face, "3", "--write-off", big], check=True)
    V, F = read_off(big)
    big_paths = write_formats(V, F, CACHE / "face_s3_io", reuse=True)
    formats = list(big_paths)
    timing = subprocess.run([reader_bench, "time"] + [big_paths[f] for f in formats],
                            capture_output=True, text=True, check=True).stdout
    speed = []
    for fmt, line in zip(formats, timing.splitlines()):
        m = re.match(r"(\S+) ours ([\d.]+) s \((\d+) v, (\d+) f.*?\) vcglib ([\d.]+) s \((\d+) v, "
                     r"(\d+) f", line)
        ours, vcg = float(m.group(2)), float(m.group(5))
        same = m.group(3) == m.group(6) and m.group(4) == m.group(7)
        speed.append(f"| {fmt.upper()} | {ours:.2f} | {vcg:.2f} | {vcg / ours:.1f}× | "
                     f"{'yes' if same else 'no'} |")

    # Bad input.
    rng = random.Random(20261201)
    V0, F0 = read_off(SEED_MESH)
    seed_paths = write_formats(V0, F0, work / "seed")
    cases = damaged(seed_paths, work, rng)
    for path in sorted((REPO / "resources" / "meshes" / "invalid").glob("*.off")):
        cases.append(("off", "invalid/" + path.stem, path.read_bytes()))
    counts = {r: collections.Counter() for r in ("ours", "vcglib")}
    examples = {r: [] for r in counts}
    per_format = collections.Counter()
    for i, (fmt, name, data) in enumerate(cases):
        path = work / f"case{i}.{fmt.split()[0]}"
        path.write_bytes(data)
        per_format[fmt] += 1
        for reader in counts:
            kind, detail = classify(reader_bench, reader, path)
            counts[reader][kind] += 1
            if kind in ("crashed", "hung", "bad index") and len(examples[reader]) < 6:
                examples[reader].append(f"{fmt} {name}: {kind} {detail}".strip())
        path.unlink()

    lines = ["Reading the 1.65M-vertex mesh (face.off, 3 midpoint subdivisions: "
             f"{len(V):,} vertices, {len(F):,} faces), best of 3, seconds:", "",
             "| format | ours | vcglib | vcglib / ours | same mesh |", "| --- | --- | --- | --- | --- |"]
    lines += speed
    lines += ["", f"Bad input: {len(cases)} files ({', '.join(f'{n} {f.upper()}' for f, n in sorted(per_format.items()))}; "
              "damaged copies of nefertiti from a fixed seed, and the bundled invalid meshes), each "
              "read once per reader in its own process. *non-finite*: a nan or inf coordinate reached the mesh (both pipelines then refuse it in the core); *bad index*: a face index out of range reached the mesh:", "",
              "| reader | " + " | ".join(CLASSES) + " |", "| --- |" + " --- |" * len(CLASSES)]
    for reader in counts:
        lines.append(f"| {reader} | " + " | ".join(str(counts[reader][c]) for c in CLASSES) + " |")
    for reader in counts:
        if examples[reader]:
            lines.append("")
            lines.append(f"{reader}, the first crashes and bad indices: " +
                         "; ".join(examples[reader]) + ".")
    png_bench = bin_dir / "sdp_png_bench"
    if png_bench.exists():
        out = subprocess.run([png_bench, work], capture_output=True, text=True, check=True).stdout
        lines += ["", "The checkerboard PNG (16 squares), our writer (zlib's deflate, no PNG filters) "
                  "against libpng's defaults, best of 3; both files decoded by libpng and compared "
                  "with the pixels:", "",
                  "| pixels | ours s | ours bytes | libpng s | libpng bytes | both decode to the pixels |",
                  "| --- | --- | --- | --- | --- | --- |"]
        for line in out.splitlines():
            w = line.split()
            lines.append(f"| {w[0]}² | {w[2]} | {int(w[4]):,} | {w[8]} | {int(w[10]):,} | "
                         f"{'yes' if w[6] == w[12] == 'decodes' else 'NO'} |")
    body = "\n".join(lines)
    RESULTS.mkdir(parents=True, exist_ok=True)
    (RESULTS / "readers.md").write_text(body + "\n")
    print(body)
    if args.doc:
        doc = pathlib.Path(args.doc)
        text = doc.read_text()
        pattern = re.compile(r"(<!-- bench:readers -->\n).*?(<!-- /bench:readers -->)", re.S)
        doc.write_text(pattern.sub(lambda m: m.group(1) + body + "\n" + m.group(2), text))


if __name__ == "__main__":
    main()
