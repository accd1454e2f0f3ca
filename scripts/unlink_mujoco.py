#!/usr/bin/env python3
"""Takes libmujoco out of the wheel's link table: scripts/wheel.sh, before auditwheel.

    unlink_mujoco.py <wheel> <soname> <patchelf>

The extension is linked against libmujoco.so.3.17.0, which the `mujoco` wheel ships (the
package depends on it). A library named in DT_NEEDED that is neither in the wheel nor in
the manylinux policy makes auditwheel judge the whole wheel plain `linux_x86_64`, whatever
its symbol versions allow. So the entry and the RUNPATH that pointed at the mujoco wheel
are removed here, and `logo_rl/__init__.py` loads that same libmujoco with RTLD_GLOBAL
before it imports the extension: its symbols are then found at load time, as they were
through DT_NEEDED. The wheel is rewritten in place, its RECORD with the new hash.
"""

import base64
import hashlib
import subprocess
import sys
import tempfile
import zipfile
from pathlib import Path


def record_hash(data: bytes) -> str:
    digest = hashlib.sha256(data).digest()
    return "sha256=" + base64.urlsafe_b64encode(digest).rstrip(b"=").decode()


def main() -> None:
    if len(sys.argv) != 4:
        sys.exit(__doc__.strip().splitlines()[2].strip())
    wheel, soname, patchelf = Path(sys.argv[1]), sys.argv[2], sys.argv[3]
    with zipfile.ZipFile(wheel) as z:
        entries = [(info, z.read(info)) for info in z.infolist()]
    extensions = [info.filename for info, _ in entries if info.filename.endswith(".so")]
    if len(extensions) != 1:
        sys.exit(f"unlink_mujoco: {wheel}: expected one extension module, found {extensions}")
    (extension,) = extensions
    with tempfile.TemporaryDirectory() as tmp:
        so = Path(tmp) / "ext.so"
        so.write_bytes(next(data for info, data in entries if info.filename == extension))
        needed = subprocess.run([patchelf, "--print-needed", so], check=True,
                                capture_output=True, text=True).stdout.split()
        if soname not in needed:
            sys.exit(f"unlink_mujoco: {extension} does not name {soname} (it names {needed})")
        subprocess.run([patchelf, "--remove-needed", soname, "--remove-rpath", so], check=True)
        patched = so.read_bytes()
    record_name = next(info.filename for info, _ in entries
                       if info.filename.endswith(".dist-info/RECORD"))
    rows = []
    for info, data in entries:
        if info.filename == record_name or info.is_dir():
            continue
        data = patched if info.filename == extension else data
        rows.append(f"{info.filename},{record_hash(data)},{len(data)}")
    rows.append(f"{record_name},,")
    out = wheel.with_suffix(".tmp")
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as z:
        for info, data in entries:
            if info.filename == extension:
                data = patched
            elif info.filename == record_name:
                data = ("\n".join(rows) + "\n").encode()
            z.writestr(info, data)
    out.replace(wheel)
    print(f"unlink_mujoco: {extension}: {soname} and the RUNPATH removed")


if __name__ == "__main__":
    main()
