"""Reference readings of tractography files by the community's own readers.

nibabel (TrackVis .trk, MRtrix .tck) and trx-python (.trx) read every input under
reference/readers/ and this script writes what they read as JSON (reference/readers/fixture.json):
point counts, points, per-point data, per-streamline data, the affine, or the error.
crates/render/tests/io/reference_readers.rs reads the same inputs with our readers and compares.

Inputs (committed, so `cargo test` needs no Python):
* readers/nibabel/: nibabel's own test files (nibabel/tests/data in the wheel; nibabel is MIT
  licensed, see readers/nibabel/COPYING), copied by `--write-inputs`.
* readers/variants/: header variants nibabel's test_trk.py / test_tck.py build by patching
  simple.trk / complex.trk / simple.tck bytes (some accepted, some rejected), written by
  `--write-inputs`.
* readers/trx/: TRX files written by trx-python (positions float16/32/64, offsets
  uint32/64, dpv, dps, groups, stored and deflated), written by `--write-inputs`.

Usage:
    python reference/readers.py --write-inputs   # (re)create the inputs, then the fixtures
    python reference/readers.py --out DIR        # fixtures only (what check.sh compares)
"""

import argparse
import importlib.metadata
import json
import os
import shutil
import sys
import zipfile

import nibabel as nib
import numpy as np
from nibabel.streamlines import Tractogram
from nibabel.streamlines.trk import TrkFile
from trx import trx_file_memmap as tmm

HERE = os.path.dirname(os.path.abspath(__file__))
INPUTS = os.path.join(HERE, "readers")
NIB_DATA = os.path.join(os.path.dirname(nib.__file__), "tests", "data")
NIB_FILES = [
    "complex.trk", "complex_big_endian.trk", "empty.trk", "simple.trk", "standard.LPS.trk",
    "standard.trk", "empty.tck", "matlab_nan.tck", "multiline_header_field.tck",
    "no_header_end.tck", "no_header_end_eof.tck", "no_magic_number.tck", "simple.tck",
    "simple_big_endian.tck", "standard.tck",
]


def patched(src, edits):
    """Bytes of nibabel file `src` with (offset, bytes) edits applied."""
    with open(os.path.join(NIB_DATA, src), "rb") as f:
        b = bytearray(f.read())
    for off, val in edits:
        b[off:off + len(val)] = val
    return bytes(b)


def le_i32(v):
    return int(v).to_bytes(4, "little", signed=True)


def trk_variants():
    """Header variants of nibabel's test_trk.py (test_load_file_with_wrong_information,
    test_load_trk_version_1) and a few more header fields nibabel reads."""
    f32 = lambda vals: np.asarray(vals, "<f4").tobytes()
    v = {
        "voxel_order_LAS.trk": patched("simple.trk", [(948, b"LAS\0")]),
        "voxel_order_las.trk": patched("simple.trk", [(948, b"las\0")]),
        "voxel_order_empty.trk": patched("standard.trk", [(948, b"\0\0\0\0")]),
        "voxel_order_PSR.trk": patched("standard.trk", [(948, b"PSR\0")]),
        "voxel_order_bad.trk": patched("simple.trk", [(948, b"RRS\0")]),
        "count_zero.trk": patched("simple.trk", [(988, le_i32(0))]),
        "vox_to_ras_zero.trk": patched("standard.trk", [(440, bytes(64))]),
        "vox_to_ras_singular.trk": patched("simple.trk", [(440, f32(np.diag([0, 0, 0, 1]).ravel()))]),
        "vox_to_ras_diag234.trk": patched("standard.trk", [(440, f32(np.diag([2, 3, 4, 1]).ravel()))]),
        "version_1.trk": patched("standard.trk", [(440, f32(np.diag([2, 3, 4, 1]).ravel())), (992, le_i32(1))]),
        "version_3.trk": patched("complex.trk", [(992, le_i32(3))]),
        "version_123.trk": patched("simple.trk", [(992, le_i32(123))]),
        "hdr_size_1234.trk": patched("simple.trk", [(996, le_i32(1234))]),
        "scalar_name_bad.trk": patched("complex.trk", [(38, b"colors\x003\x004")]),
        "property_name_bad.trk": patched("complex.trk", [(240, b"colors\x003\x004")]),
        # Unnamed columns: nibabel names them "scalars" / "properties".
        "scalar_names_unset.trk": patched("complex.trk", [(38, bytes(200)), (240, bytes(200))]),
        "many_scalars.trk": patched("complex.trk", [(58, bytes(20))]),
    }
    return v


def tck_variants():
    """Header variants nibabel's TCK reader accepts or rejects."""
    with open(os.path.join(NIB_DATA, "simple.tck"), "rb") as f:
        b = f.read()
    end = b.index(b"END\n") + 4
    head, data = b[:end].decode(), b[end:]
    lines = head.split("\n")
    keep = lambda pred: "\n".join(l for l in lines if pred(l))
    off = int([l for l in lines if l.startswith("file:")][0].split()[2])
    pad = data if off == end else b[off:]
    def with_offset(h):
        h = h.encode()
        return h + pad if b"file:" not in h else None
    v = {
        "no_datatype.tck": keep(lambda l: not l.startswith("datatype")).encode(),
        "no_file.tck": keep(lambda l: not l.startswith("file")).encode(),
        "float64.tck": head.replace("Float32LE", "Float64LE").encode(),
        "separate_file.tck": head.replace("file: .", "file: other.dat").encode(),
        "trailing_bytes.tck": b"",
        "unclosed_streamline.tck": b"",
    }
    # Header variants are re-padded to the data offset so the data stay where `file:` says.
    out = {}
    for name, h in v.items():
        if name in ("no_file.tck",):
            out[name] = h + pad  # data right after END, as nibabel guesses
        elif name == "trailing_bytes.tck":
            out[name] = b + b"\0\0\0\0"
        elif name == "unclosed_streamline.tck":
            inf = np.asarray([np.inf] * 3, "<f4").tobytes()
            out[name] = b[:-24] + inf  # the last NaN triplet replaced by the Inf marker
        else:
            hb = h if len(h) <= off else None
            out[name] = hb.ljust(off, b"\n") + b[off:] if hb is not None else h + pad
    return out


def trx_inputs(outdir):
    """TRX files written by trx-python from complex.trk (data per vertex and per streamline)
    with several position / offset dtypes, groups, and deflate compression."""
    trk = nib.streamlines.load(os.path.join(NIB_DATA, "complex.trk"))
    tg = trk.tractogram
    files = {}
    for pos, off, comp in [
        ("float32", "uint32", zipfile.ZIP_STORED),
        ("float16", "uint64", zipfile.ZIP_STORED),
        ("float64", "uint32", zipfile.ZIP_DEFLATED),
    ]:
        dd = {"positions": np.dtype(pos), "offsets": np.dtype(off),
              "dpv": {"fa": np.float32, "colors": np.float64}, "dps": {"mean_curvature": np.float16,
              "mean_torsion": np.float32, "mean_colors": np.float32}}
        trx = tmm.TrxFile.from_tractogram(tg, reference=trk.header, dtype_dict=dd)
        trx.groups["first_two"] = np.array([0, 1], dtype=np.uint32)
        name = f"complex_{pos}_{off}_{'deflate' if comp else 'stored'}.trx"
        tmm.save(trx, os.path.join(outdir, name), compression_standard=comp)
        trx.close()
        files[name] = True
    # Empty tractogram.
    empty = tmm.TrxFile.from_tractogram(Tractogram(affine_to_rasmm=np.eye(4)), reference=trk.header)
    tmm.save(empty, os.path.join(outdir, "empty.trx"))
    empty.close()
    return files


def write_inputs():
    shutil.rmtree(INPUTS, ignore_errors=True)
    for sub in ("nibabel", "variants", "trx"):
        os.makedirs(os.path.join(INPUTS, sub))
    for f in NIB_FILES:
        shutil.copyfile(os.path.join(NIB_DATA, f), os.path.join(INPUTS, "nibabel", f))
    lic = os.path.join(os.path.dirname(nib.__file__), "..", f"nibabel-{nib.__version__}.dist-info", "licenses", "COPYING")
    shutil.copyfile(lic, os.path.join(INPUTS, "nibabel", "COPYING"))
    for name, b in {**trk_variants(), **tck_variants()}.items():
        with open(os.path.join(INPUTS, "variants", name), "wb") as f:
            f.write(b)
    trx_inputs(os.path.join(INPUTS, "trx"))


def flat(arrseq):
    return [float(x) for x in np.asarray(arrseq, dtype=np.float64).ravel()]


def fields(d, nitems):
    out = {}
    for k in sorted(d):
        a = np.asarray(d[k].get_data() if hasattr(d[k], "get_data") else d[k], dtype=np.float64)
        a = a.reshape(nitems, -1)
        out[k] = {"width": int(a.shape[1]), "values": [float(x) for x in a.ravel()]}
    return out


def read_nibabel(path):
    obj = nib.streamlines.load(path)
    tg = obj.tractogram
    sl = tg.streamlines
    rec = {
        "lengths": [int(n) for n in sl._lengths],
        "points": flat(sl.get_data()),
        "affine": [float(x) for x in np.asarray(tg.affine_to_rasmm if path.endswith(".tck") else
                                                 nib.streamlines.trk.get_affine_trackvis_to_rasmm(obj.header),
                                                 dtype=np.float64).ravel()],
        "per_point": fields({k: v for k, v in tg.data_per_point.items()}, int(sum(sl._lengths))),
        "per_streamline": fields(dict(tg.data_per_streamline.items()), len(sl)),
    }
    if path.endswith(".trk"):
        # The stored voxmm coordinates (for the f32 rounding bound of the affine's application).
        hdr = TrkFile._read_header(path)
        raw = [p for p, _, _ in TrkFile._read(path, hdr)]
        rec["voxmm"] = flat(np.concatenate(raw)) if raw else []
    return rec


def read_trx(path):
    trx = tmm.load(path)
    sl = trx.streamlines
    n = len(sl)
    rec = {
        "lengths": [int(x) for x in sl._lengths] if n else [],
        "points": flat(sl.get_data()) if n else [],
        "positions_dtype": str(sl.get_data().dtype) if n else None,
        "affine": [float(x) for x in np.asarray(trx.header["VOXEL_TO_RASMM"], dtype=np.float64).ravel()],
        "dimensions": [int(x) for x in trx.header["DIMENSIONS"]],
        "per_point": {k: {"width": int(v._data.shape[1]), "values": flat(v._data)} for k, v in sorted(trx.data_per_vertex.items())},
        "per_streamline": {k: {"width": int(np.asarray(v).shape[1]), "values": flat(v)} for k, v in sorted(trx.data_per_streamline.items())},
        "groups": {k: [int(i) for i in v] for k, v in sorted(trx.groups.items())},
    }
    trx.close()
    return rec


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=INPUTS)
    ap.add_argument("--write-inputs", action="store_true")
    args = ap.parse_args()
    if args.write_inputs:
        write_inputs()
    # The committed copies must be nibabel's files byte for byte.
    for f in NIB_FILES:
        with open(os.path.join(NIB_DATA, f), "rb") as a, open(os.path.join(INPUTS, "nibabel", f), "rb") as b:
            if a.read() != b.read():
                sys.exit(f"readers.py: reference/readers/nibabel/{f} differs from nibabel {nib.__version__}'s copy")
    out = {"nibabel": nib.__version__, "trx-python": importlib.metadata.version("trx-python"), "files": {}}
    for sub in ("nibabel", "variants", "trx"):
        for f in sorted(os.listdir(os.path.join(INPUTS, sub))):
            if f in ("COPYING", "fixture.json"):
                continue
            path = os.path.join(INPUTS, sub, f)
            try:
                rec = read_trx(path) if f.endswith(".trx") else read_nibabel(path)
                rec = {"accepted": True, **rec}
            except Exception as e:  # the reference reader refuses the file
                rec = {"accepted": False, "error": f"{type(e).__name__}: {e}"}
            out["files"][f"{sub}/{f}"] = rec
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "fixture.json"), "w") as fh:
        json.dump(out, fh, indent=1, sort_keys=True)
        fh.write("\n")


if __name__ == "__main__":
    main()
