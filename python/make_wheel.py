"""Packs the Python package a build assembled into a wheel (python/CMakeLists.txt runs it on every build).

    python3 make_wheel.py --package BUILD/python/pheromesh --scenarios SRC/scenarios --version 0.1.0 --out DIR

Run it with the interpreter the extension was built for: the wheel's tag
(cp311-cp311-linux_x86_64, ...) is that interpreter's. The wheel holds the
package (its modules, the extension, _build.py) and the shipped scenarios
(pheromesh/scenarios/, which the extension searches first); not the
`pheromesh` programs that run() and replay() start (pheromesh.program()).
Only the standard library: a wheel is a zip file with a RECORD of hashes
(PEP 427), and this machine's Python has no `wheel` tool to rely on.
"""

from __future__ import annotations

import argparse
import base64
import hashlib
import os
import sys
import sysconfig
import zipfile
from pathlib import Path
from typing import List, Tuple

# Entries get a fixed time, so that the same files make the same wheel.
_EPOCH = (1980, 1, 1, 0, 0, 0)


def wheel_tag() -> str:
    impl = f"cp{sys.version_info.major}{sys.version_info.minor}"
    platform = sysconfig.get_platform().replace("-", "_").replace(".", "_")
    return f"{impl}-{impl}-{platform}"


def _record_hash(data: bytes) -> str:
    digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
    return f"sha256={digest}"


def _files(package: Path, scenarios: Path) -> List[Tuple[str, Path]]:
    out = []
    for p in sorted(package.iterdir()):
        if p.is_file() and (p.suffix in (".py", ".so") or p.name == "py.typed"):
            out.append((f"pheromesh/{p.name}", p))
    if not any(name.endswith(".so") for name, _ in out):
        raise SystemExit(f"make_wheel: no extension (_pheromesh*.so) in {package}")
    for p in sorted(scenarios.glob("*.textproto")):
        out.append((f"pheromesh/scenarios/{p.name}", p))
    return out


def build(package: Path, scenarios: Path, version: str, out: Path) -> Path:
    tag = wheel_tag()
    dist_info = f"pheromesh-{version}.dist-info"
    py = f"{sys.version_info.major}.{sys.version_info.minor}"
    metadata = (
        "Metadata-Version: 2.1\n"
        "Name: pheromesh\n"
        f"Version: {version}\n"
        "Summary: A UAV swarm that coordinates through digital pheromones: scenarios, the in-process "
        "simulator, sweeps and swarms of real processes from Python\n"
        f"Requires-Python: =={py}.*\n"
        "Requires-Dist: numpy\n"
        "Provides-Extra: pandas\n"
        "Requires-Dist: pandas; extra == \"pandas\"\n"
    )
    wheel = (
        "Wheel-Version: 1.0\n"
        "Generator: pheromesh python/make_wheel.py\n"
        "Root-Is-Purelib: false\n"
        f"Tag: {tag}\n"
    )
    entries = [(name, path.read_bytes()) for name, path in _files(package, scenarios)]
    entries += [(f"{dist_info}/METADATA", metadata.encode()), (f"{dist_info}/WHEEL", wheel.encode())]
    record = "".join(f"{name},{_record_hash(data)},{len(data)}\n" for name, data in entries)
    record += f"{dist_info}/RECORD,,\n"
    entries.append((f"{dist_info}/RECORD", record.encode()))

    out.mkdir(parents=True, exist_ok=True)
    target = out / f"pheromesh-{version}-{tag}.whl"
    partial = target.with_name(target.name + ".partial")
    with zipfile.ZipFile(partial, "w", compression=zipfile.ZIP_DEFLATED) as z:
        for name, data in entries:
            info = zipfile.ZipInfo(name, date_time=_EPOCH)
            info.compress_type = zipfile.ZIP_DEFLATED
            # rwx for the extension, rw for the rest (a zip entry's Unix mode sits in the high 16 bits).
            info.external_attr = (0o100755 if name.endswith(".so") else 0o100644) << 16
            z.writestr(info, data)
    os.replace(partial, target)  # a wheel is whole or absent
    return target


def main() -> None:
    a = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    a.add_argument("--package", type=Path, required=True, help="the assembled package folder (build/python/pheromesh)")
    a.add_argument("--scenarios", type=Path, required=True, help="the shipped scenarios (the source tree's scenarios/)")
    a.add_argument("--version", required=True)
    a.add_argument("--out", type=Path, required=True, help="the folder for the wheel")
    a.add_argument("--stamp", type=Path, help="a file to touch once the wheel is written (the build's output)")
    args = a.parse_args()
    target = build(args.package, args.scenarios, args.version, args.out)
    if args.stamp:
        args.stamp.write_text(f"{target.name}\n")


if __name__ == "__main__":
    main()
