#!/usr/bin/env python3
"""Bundles built aperture binaries with the shared libraries they need, so the
benchmarks run on a Linux machine that has a GPU driver but none of our Debian
packages (docs/performance.md, "On a GPU").

Usage: scripts/portable-bundle.py OUT_DIR BINARY...

Copies the binaries, the image plugin beside them (aal_oiio_images.so, which
the tools open to read and write images: terrain/io/image_files.h) and every
library they load into OUT_DIR (binaries and the plugin at the top, libraries
in lib/; the shaders are built into the binaries), except the C runtime (libc, libm,
libstdc++, libgcc_s, the loader: the target's newer ones serve, and its GPU
driver needs them). OpenImageIO links many codec libraries
that our tools never call (video, DICOM, OpenVDB, camera raw, HEIF, OpenCV);
with their dependencies they are ~300 MB, so each is replaced by a stand-in
that defines the symbols the kept libraries import (functions that return a
pointer to zeros: version strings read as empty). PROJ is kept: GDAL places
every DEM with it (docs/dem-input.md), and its database (proj.db) and GDAL's
data files are copied to OUT_DIR/share/proj and OUT_DIR/share/gdal.
Run on the target with LD_LIBRARY_PATH=OUT_DIR/lib, PROJ_DATA=OUT_DIR/share/proj
and GDAL_DATA=OUT_DIR/share/gdal.
"""
import os
import re
import shutil
import subprocess
import sys

LIBRARY_DIRS = ["/lib/x86_64-linux-gnu", "/usr/lib/x86_64-linux-gnu"]
STAND_INS = [
    "libopencv_core.so.406", "libopencv_imgproc.so.406", "libopencv_videoio.so.406",
    "libdcmimage.so.17", "libdcmimgle.so.17", "libdcmdata.so.17", "liboflog.so.17",
    "libofstd.so.17", "libavcodec.so.59", "libavformat.so.59", "libavutil.so.57",
    "libswscale.so.6", "libheif.so.1", "libopenvdb.so.10.0", "libraw_r.so.20"]
DATA_DIRS = {"proj": "/usr/share/proj", "gdal": "/usr/share/gdal"}
C_RUNTIME = {"libc.so.6", "libm.so.6", "ld-linux-x86-64.so.2", "libpthread.so.0",
             "libdl.so.2", "librt.so.1", "libstdc++.so.6", "libgcc_s.so.1"}


def run(*args):
    return subprocess.run(args, capture_output=True, text=True, check=True).stdout


def needed(path):
    return re.findall(r"NEEDED.*\[(.*)\]", run("readelf", "-d", path))


def find_library(name):
    for directory in LIBRARY_DIRS:
        path = os.path.join(directory, name)
        if os.path.exists(path):
            return path
    # Elsewhere on the loader's path (GDAL's armadillo sits in /usr/lib).
    for line in run("ldconfig", "-p").splitlines():
        fields = line.split()
        if fields and fields[0] == name and "x86-64" in line:
            return fields[-1]
    sys.exit(f"portable-bundle: {name} not found in {LIBRARY_DIRS} nor by ldconfig")


def kept_libraries(binaries):
    kept, seen, todo = {}, set(), list(binaries)
    while todo:
        for name in needed(todo.pop()):
            if name in seen or name in C_RUNTIME:
                continue
            seen.add(name)
            if name in STAND_INS:
                continue
            kept[name] = find_library(name)
            todo.append(kept[name])
    return kept


def imported_symbols(paths):
    symbols = set()
    for path in paths:
        for line in run("nm", "-D", "--undefined-only", path).splitlines():
            fields = line.split()
            if fields and fields[0] in ("U", "w"):
                symbols.add(fields[-1])
    return symbols


def write_stand_in(name, imported, out_dir):
    """A library named `name` defining what the kept ones import from it."""
    by_version, assembly = {}, [".text\n"]
    for line in run("nm", "-D", "--defined-only", find_library(name)).splitlines():
        fields = line.split()
        if len(fields) < 3:
            continue
        symbol, _, version = fields[2].partition("@")
        version = version.lstrip("@")
        if symbol not in imported and f"{symbol}@{version}" not in imported:
            continue
        by_version.setdefault(version, []).append(symbol)
        assembly.append(f'.globl "{symbol}"\n.type "{symbol}",@function\n'
                        f'"{symbol}":\n lea zeros(%rip), %rax\n ret\n')
    assembly.append(".bss\n.balign 64\nzeros: .zero 65536\n")
    source = os.path.join(out_dir, name + ".s")
    script = os.path.join(out_dir, name + ".map")
    with open(source, "w") as f:
        f.write("".join(assembly))
    with open(script, "w") as f:
        for version, symbols in by_version.items():
            if version:
                f.write(version + " { global:\n" + "".join(f' "{s}";\n' for s in symbols) + "};\n")
    command = ["gcc", "-shared", "-nostdlib", "-o", os.path.join(out_dir, name), source,
               "-Wl,-soname," + name]
    if os.path.getsize(script) > 0:
        command.append("-Wl,--version-script=" + script)
    subprocess.run(command, check=True)
    os.remove(source)
    os.remove(script)
    return sum(len(s) for s in by_version.values())


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    out_dir, binaries = sys.argv[1], sys.argv[2:]
    lib_dir = os.path.join(out_dir, "lib")
    os.makedirs(lib_dir, exist_ok=True)
    plugin = os.path.join(os.path.dirname(os.path.abspath(binaries[0])), "aal_oiio_images.so")
    if os.path.exists(plugin) and plugin not in map(os.path.abspath, binaries):
        binaries.append(plugin)
    for binary in binaries:
        shutil.copy(binary, out_dir)
    for name, source in DATA_DIRS.items():
        shutil.copytree(source, os.path.join(out_dir, "share", name), dirs_exist_ok=True)
    kept = kept_libraries(binaries)
    for name, path in kept.items():
        shutil.copy(os.path.realpath(path), os.path.join(lib_dir, name))
    imported = imported_symbols(list(kept.values()) + binaries)
    for name in STAND_INS:
        print(f"{name}: stand-in with {write_stand_in(name, imported, lib_dir)} symbols")
    print(f"{len(kept)} libraries copied to {lib_dir}")


if __name__ == "__main__":
    main()
