#!/usr/bin/env python3
"""Interop of program download (CiA 302-3) between the virtual charger
(examples/charger --program-store FILE) and python-canopen as the master.

python-canopen stops the program (1F51h:01 = 0), clears it (= 3),
block-downloads a 5000-byte random image into 1F50h:01 (its
BlockDownloadStream, CRC requested), reads 1F57h:01 (flash status: no
error, not in progress) and 1F56h:01 (the software identification: the
CRC-32 the charger's file store computes, zlib's), starts the program
(= 1) and reads 1F51h:01 back (1, started). A second download while the
program runs must be refused with 08000022h. The file the charger wrote
must equal the image byte for byte.

usage: program_download_interop.py PATH/TO/charger
"""

import os
import random
import sys
import tempfile
import time
import zlib

import canopen
from canopen.objectdictionary import ObjectDictionary
from pipebus import Cases, PipeBus, wait_until

CHARGER = 10
BATTERY = 1
IMAGE_LEN = 5000

CASES = Cases()
check = CASES.check



def refusal(op):
    """The SDO abort code `op` ends with, or None when it succeeds."""
    try:
        op()
    except canopen.SdoAbortedError as e:
        return e.code
    return None

def block_download(charger, data):
    with charger.sdo.open(0x1F50, 1, "wb", block_transfer=True, size=len(data)) as f:
        f.write(data)


def u32(charger, index):
    return int.from_bytes(charger.sdo.upload(index, 1), "little")


def main():
    exe = sys.argv[1]
    image = random.Random(302).randbytes(IMAGE_LEN)
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "program.bin")
        bus = PipeBus([exe, "--node-id", str(CHARGER), "--battery-node", str(BATTERY),
                       "--linger-ms", "0", "--program-store", path])
        net = canopen.Network(bus)
        net.connect()
        charger = net.add_node(CHARGER, ObjectDictionary())
        charger.sdo.RESPONSE_TIMEOUT = 2.0
        try:
            check("the charger boots (70A#00)",
                  wait_until(lambda: any(i == 0x700 + CHARGER for _, i, _ in bus.seen), 3))
            check("1F51h:00 = 1 program", charger.sdo.upload(0x1F51, 0) == b"\x01")
            check("no program at start: 1F51h:01 reads 3 (no program available)",
                  charger.sdo.upload(0x1F51, 1) == b"\x03")
            charger.sdo.download(0x1F51, 1, b"\x00")
            charger.sdo.download(0x1F51, 1, b"\x03")
            check("cleared: 1F57h:01 = 0 (no error)", u32(charger, 0x1F57) == 0)
            t0 = time.time()
            block_download(charger, image)
            took = time.time() - t0
            # The charger's answers on 58Ah: block download responses (scs 5,
            # A0h..A7h), so the image went by block, not segmented.
            block = [d for ts, i, d in bus.seen if i == 0x580 + CHARGER and ts >= t0 and d[0] & 0xE0 == 0xA0]
            check(f"block download of {IMAGE_LEN} bytes into 1F50h:01 by block ({took:.2f} s)",
                  len(block) >= 3, len(block))
            status = u32(charger, 0x1F57)
            check("1F57h:01 = 0: not in progress, no error", status == 0, hex(status))
            ident = u32(charger, 0x1F56)
            check("1F56h:01 = the image's CRC-32", ident == zlib.crc32(image),
                  f"{ident:08X}h vs {zlib.crc32(image):08X}h")
            check("downloaded, stopped: 1F51h:01 reads 0", charger.sdo.upload(0x1F51, 1) == b"\x00")
            charger.sdo.download(0x1F51, 1, b"\x01")
            check("started: 1F51h:01 reads 1", charger.sdo.upload(0x1F51, 1) == b"\x01")
            code = refusal(lambda: block_download(charger, image[:100]))
            check("a download while started is refused with 08000022h",
                  code == 0x08000022, "accepted" if code is None else hex(code))
            code = refusal(lambda: charger.sdo.download(0x1F51, 1, b"\x03"))
            check("clear while started is refused with 08000022h",
                  code == 0x08000022, "accepted" if code is None else hex(code))
            check("1F56h:01 unchanged after the refusals", u32(charger, 0x1F56) == zlib.crc32(image))
        finally:
            net.disconnect()
        with open(path, "rb") as f:
            written = f.read()
        check("the file the charger wrote equals the image", written == image,
              f"{len(written)} bytes")
        check("the store reported the download in words",
              any("5000 bytes written" in l for l in bus.stderr_lines), bus.stderr_lines[-5:])
    CASES.finish()


if __name__ == "__main__":
    main()
