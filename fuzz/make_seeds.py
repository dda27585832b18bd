#!/usr/bin/env python3
"""Writes the seed corpora fuzz/seeds/TARGET/: one small file per real shape,
taken from the tests' own vectors. Rerunnable: rewrites the files it owns.

Covered so far: decode_frame (layout in fuzz/fuzz_targets/decode_frame.rs:
flags byte, identifier little-endian, data); blf (a chunk-size byte, a flag
byte, then a BLF file: stored and zlib containers, v1 and v2 object
headers, an object straddling two containers, CAN FD and error objects);
asc_line (a byte choosing the base line, then ASC lines); trace_line (one
file per trace format); decoder_run (the tests' own logs under several
option sets); eds_parse (an EDS and a DCF); sdo_wire (one SDO frame per command
kind); concise_dcf (the unit tests' concise DCF vectors, src/od/concise_tests.rs);
pcap (a chunk-size byte, a flag byte, then a pcap or pcapng file: both
byte orders, nanosecond times, two interfaces, Simple and obsolete Packet
Blocks, a skipped block, CAN FD, error and Ethernet packets)."""
import pathlib
import struct
import zlib

HERE = pathlib.Path(__file__).resolve().parent


def frame(cob_id, data_hex, remote=False):
    data = bytes.fromhex(data_hex)
    flags = (len(data) << 4) | (0x02 if remote else 0)
    return bytes([flags]) + cob_id.to_bytes(2, "little") + data


# (file name, bytes): frames from tests/sdo/vectors.rs and the CiA 301 services.
DECODE_FRAME = [
    ("nmt_start_all", frame(0x000, "01 00")),
    ("sync", frame(0x080, "")),
    ("emcy_node_10", frame(0x08A, "10 81 11 00 00 00 00 00")),
    ("time", frame(0x100, "00 00 00 00 00 00")),
    ("tpdo1_node_10", frame(0x18A, "01 02 03 04 05 06 07 08")),
    ("sdo_upload_request_1018_01", frame(0x602, "40 18 10 01 00 00 00 00")),
    ("sdo_expedited_upload_response", frame(0x582, "43 18 10 01 04 00 00 00")),
    ("sdo_block_upload_initiate", frame(0x602, "A4 00 20 00 7F 00 00 00")),
    ("sdo_abort", frame(0x582, "80 00 20 00 00 00 02 06")),
    ("heartbeat_operational", frame(0x70A, "05")),
    ("bootup", frame(0x70A, "00")),
    ("guarding_rtr", frame(0x70A, "", remote=True)),
    ("lss_switch_global", frame(0x7E5, "04 01 00 00 00 00 00 00")),
]


def blf_object(obj_type, body, version=1, flags=2, ticks=0):
    """A BLF object: base header, v1 (32 bytes) or v2 (40) header, body,
    size % 4 padding."""
    header = 32 if version == 1 else 40
    size = header + len(body)
    o = b"LOBJ" + struct.pack("<HHLL", header, version, size, obj_type)
    o += struct.pack("<LHHQ", flags, 0, 0, ticks)
    if version == 2:
        o += struct.pack("<Q", ticks)
    return o + body + b"\0" * (size % 4)


def blf_can(channel, flags, dlc, can_id, data):
    return struct.pack("<HBBL8s", channel, flags, dlc, can_id, data)


def blf_container(method, payload, declared):
    size = 32 + len(payload)
    o = b"LOBJ" + struct.pack("<HHLL", 16, 1, size, 10)
    o += struct.pack("<H6xL4x", method, declared)
    return o + payload + b"\0" * (size % 4)


def blf_file(containers):
    header = b"LOGG" + struct.pack("<L", 144) + bytes([5, 0, 0, 0, 2, 6, 8, 1])
    header += struct.pack("<QQLL", 0, 0, 3, 0)
    header += struct.pack("<8H", 2025, 9, 4, 4, 3, 14, 13, 603) + bytes(16)
    return header + bytes(144 - len(header)) + b"".join(containers)


def blf_seeds():
    stream = b"".join(
        [
            blf_object(1, blf_can(1, 0, 8, 0x18A, bytes.fromhex("7413454E70000000")), ticks=1_000_000),
            blf_object(86, blf_can(2, 1, 1, 0x70A, b"\x05" + bytes(7)) + bytes(8), version=2, flags=1, ticks=150),
            blf_object(1, blf_can(1, 0x80, 1, 0x70A, bytes(8)), ticks=3_000_000),
            blf_object(1, blf_can(1, 0, 2, 0x80000000 | 0x18DAF110, b"\x01\x02" + bytes(6))),
            blf_object(100, bytes(84)),
            blf_object(73, bytes(32)),
            blf_object(65, b"text of odd length"),
        ]
    )
    stored = blf_file([blf_container(0, stream[:70], 70), blf_container(0, stream[70:], len(stream) - 70)])
    packed = blf_file([blf_container(2, zlib.compress(stream), len(stream))])
    return [
        ("stored_whole", bytes([255, 0]) + stored),
        ("stored_small_chunks", bytes([0, 0]) + stored),
        ("zlib", bytes([7, 0]) + packed),
        ("objects_after_header", bytes([16, 1]) + stream),
    ]


ASC = """date Thu Sep 04 03:14:13.603 2025
base hex  timestamps absolute
internal events logged
Begin Triggerblock Thu Sep 04 03:14:13.603 2025
   0.000000 Start of measurement
   1.234567 1  18A             Rx   d 8 74 13 45 4E 70 00 00 00  Length = 240000 BitCount = 124 ID = 394
   1.244251 1  70A             Rx   r 1
   1.331259 1  18DAF110x       Tx   d 2 01 02
   1.400000 1  ErrorFrame
   1.500000 CANFD   1 Rx 18A  0 0 8 8 74 13 45 4E 70 00 00 00
   1.600000 1  Statistic: D 0 R 0 XD 0 XR 0 E 0 O 0 B 0.00%
   2.000000 1  18A             Rx   d 9 00 00 00 00 00 00 00 00
End TriggerBlock
"""


def asc_seeds():
    return [
        ("python_can_hex", bytes([0]) + ASC.encode()),
        ("decimal_relative", bytes([3]) + ASC.replace("18A ", "394 ").encode()),
    ]


# One file per trace format, each with a header and lines of the shapes its
# own tools write (the module docs of src/trace/ show them). trace_line's
# input is (format selector byte, delta-times byte, text); the selector
# indexes None (detect), candump log, candump screen, .trc, ASC, CSV.
TRACES = [
    ("candump_log", 1, """(1756955653.603308) can1 000#010A
(1756955653.612992) can1 08A#0000000000000000
(1756955653.669466) can1 18A#7C13464E70000000
(1756955653.699699) can1 701#05
(1756955654.000000) can1 701#R
(1756955654.100000) can1 18DAF110#0102
(1756955654.200000) can1 123##100112233445566778899AABB
"""),
    ("candump_screen", 2, """  can0  18A   [8]  74 13 45 4E 70 00 00 00
  can0  701   [1]  remote request
(1700000000.123456)  can0  70A   [1]  05
  can0  RX - -  18A   [8]  74 13 45 4E 70 00 00 00
  can0  20000004   [8]  00 04 00 00 00 00 00 00   ERRORFRAME
  can0  123  [12]  00 11 22 33 44 55 66 77 88 99 AA BB
"""),
    ("trc_1_0", 3, """;##########################################################################
;   Start time: 04.09.2025 03:14:13.603.0
;##########################################################################
     1)      1841  0300  8  00 00 00 00 00 00 00 00
     2)      1842  070A  1  05
     3)      1843  0701  1  RTR
"""),
    ("trc_1_1", 3, """;$FILEVERSION=1.1
;$STARTTIME=45904.1348796
     1)      1841.6  Rx         0300  8  00 00 00 00 00 00 00 00
     2)      1842.0  Tx         070A  1  05
     3)      1843.2  Warng      FFFFFFFF  4  00 00 00 08 BUSHEAVY
"""),
    ("trc_2_1", 3, """;$FILEVERSION=2.1
;$STARTTIME=45904.1348796
;$COLUMNS=N,O,T,B,I,d,R,L,D
     1      1059.900 DT 1      0300 Rx -  7  00 00 00 00 04 00 00
     2      1060.100 RR 1      0701 Rx -  1
     3      1061.000 DT 1  18DAF110 Tx -  2  01 02
     4      1062.000 ER 1         - Rx -  5  00 00 08 01 00
"""),
    ("asc", 4, ASC),
    ("python_can_csv", 5, """timestamp,arbitration_id,extended,remote,error,dlc,data
1756955653.603308,0x18a,0,0,0,8,dBNFTnAAAAA=
1756955653.612992,0x70a,0,1,0,1,
1756955653.700000,0x18daf110,1,0,0,2,AQI=
"""),
]


def trace_line_seeds():
    return [(name, bytes([sel, 0]) + text.encode()) for name, sel, text in TRACES] + [
        ("candump_screen_delta", bytes([2, 1]) + b"(000.000211)  can0  18A   [8]  74 13 45 4E 70 00 00 00\n"),
    ]


# decoder_run: the first byte picks one of its option sets (SETS in
# fuzz/fuzz_targets/decoder_run.rs), the rest is the trace.
def decoder_run_seeds():
    sdo = (HERE.parent / "tests" / "data" / "sdo-sample.log").read_bytes()
    download = (HERE.parent / "tests" / "data" / "program-download.log").read_bytes()
    session = (HERE.parent / "tests" / "data" / "virtual-session.log").read_bytes()
    traces = {name: text.encode() for name, _, text in TRACES}
    return [
        ("sdo_sample_words", bytes([0]) + sdo),
        ("sdo_sample_json_summary", bytes([1]) + sdo),
        ("session_csv_strict", bytes([2]) + b"".join(session.splitlines(True)[:40])),
        ("session_roles_summary", bytes([3]) + session),
        ("program_download_roles_json", bytes([4]) + download),
        ("screen_check", bytes([5]) + traces["candump_screen"]),
        ("screen_delta", bytes([6]) + b"(000.000211)  can0  18A   [8]  74 13 45 4E 70 00 00 00\n"
         b"(000.100000)  can0  70A   [1]  05\n"),
        ("trc_sdo_channels", bytes([7]) + traces["trc_2_1"]),
        ("asc_pdo", bytes([8]) + traces["asc"].replace(b"\r", b"")),
        ("csv_capture_mapping", bytes([9]) + traces["python_can_csv"]),
    ]


# eds_parse: EDS and DCF text, CRLF as tools write it.
EDS = """[FileInfo]\r
FileName=seed.eds\r
FileVersion=1\r
[DeviceInfo]\r
VendorName=seed\r
NrOfRXPDO=1\r
NrOfTXPDO=1\r
[MandatoryObjects]\r
SupportedObjects=2\r
1=0x1000\r
2=0x1001\r
[OptionalObjects]\r
SupportedObjects=3\r
1=0x1008\r
2=0x1017\r
3=0x1800\r
[1000]\r
ParameterName=Device type\r
ObjectType=0x7\r
DataType=0x0007\r
AccessType=ro\r
DefaultValue=0x000001A2\r
PDOMapping=0\r
[1001]\r
ParameterName=Error register\r
DataType=0x0005\r
AccessType=ro\r
DefaultValue=0\r
PDOMapping=1\r
[1008]\r
ParameterName=Manufacturer Device Name\r
DataType=0x0009\r
AccessType=const\r
DefaultValue=IC650 charger with a long name\r
[1017]\r
ParameterName=Producer heartbeat time\r
DataType=6\r
AccessType=rw\r
DefaultValue=1000\r
[1800]\r
ParameterName=TPDO 0\r
ObjectType=9\r
SubNumber=2\r
[1800sub0]\r
ParameterName=Highest sub-index\r
DataType=5\r
AccessType=ro\r
DefaultValue=1\r
[1800sub1]\r
ParameterName=COB-ID\r
DataType=7\r
AccessType=rw\r
DefaultValue=$NODEID+0x180\r
"""


def eds_parse_seeds():
    dcf = EDS.replace("FileName=seed.eds", "FileName=seed.dcf").replace(
        "DefaultValue=1000\r\n", "DefaultValue=1000\r\nParameterValue=\r\n"
    ) + "[DeviceComissioning]\r\nNodeID=10\r\nBaudrate=500\r\n"
    return [("eds", EDS.encode()), ("dcf_empty_parameter_value", dcf.encode())]


# sdo_wire: the 8 data bytes of one SDO frame per command kind, from
# tests/data/sdo-sample.log and tests/data/program-download.log (the real
# exchanges of the tests) and the abort of tests/sdo/vectors.rs.
SDO_WIRE = [
    ("upload_initiate_request", "40 18 10 01 00 00 00 00"),
    ("upload_expedited_response", "43 18 10 01 04 00 00 00"),
    ("download_expedited_request", "2B 17 10 00 A0 0F 00 00"),
    ("download_initiate_response", "60 17 10 00 00 00 00 00"),
    ("upload_segmented_response", "41 08 10 00 1A 00 00 00"),
    ("upload_segment_request", "60 00 00 00 00 00 00 00"),
    ("upload_segment", "00 54 69 6E 79 20 4E 6F"),
    ("upload_last_segment", "15 69 6E 73 20 21 00 00"),
    ("download_segmented_request", "21 00 20 00 0D 00 00 00"),
    ("download_segment", "00 41 20 6C 6F 6E 67 20"),
    ("download_last_segment", "13 73 74 72 69 6E 67 00"),
    ("abort", "80 18 10 01 11 00 09 06"),
    ("block_download_initiate", "C6 50 1F 01 40 00 00 00"),
    ("block_download_initiate_response", "A4 50 1F 01 7F 00 00 00"),
    ("block_segment", "01 57 5C 70 64 C7 45 89"),
    ("block_last_segment", "8A AB 00 00 00 00 00 00"),
    ("block_ack", "A2 0A 7F 00 00 00 00 00"),
    ("block_download_end", "D9 DD D0 00 00 00 00 00"),
    ("block_end_response", "A1 00 00 00 00 00 00 00"),
    ("block_upload_initiate", "A4 08 10 00 7F 00 00 00"),
    ("block_upload_start", "A3 00 00 00 00 00 00 00"),
    ("short_frame", "40 18 10"),
]


def concise(entries):
    """A concise DCF (CiA 302-3 section 4): count, then index, sub, size, data."""
    out = struct.pack("<I", len(entries))
    for index, sub, data in entries:
        out += struct.pack("<HBI", index, sub, len(data)) + data
    return out


CONCISE_DCF = [
    ("empty", concise([])),
    ("two_entries", concise([(0x1017, 0, b"\xf4\x01"), (0x1800, 1, bytes.fromhex("85010040"))])),
    ("zero_size", concise([(0x1F50, 1, b"")])),
    ("count_too_large", b"\x03" + concise([(0x1017, 0, b"\xf4\x01")])[1:]),
    ("size_past_end", concise([(0x1017, 0, b"\xf4\x01")])[:-1]),
]


def mf4_seeds():
    """Small MF4 files of other tools (the fuzz target's first byte: 1 for
    flate2's zlib): python-can's MF4Writer at each compression level (with a
    remote and an error frame, in data groups of their own) and asammdf's
    MDF 4.20 in 256-byte fragments (an ##HL / ##DL list). Needs python-can
    and asammdf; without them the committed seeds are kept."""
    try:
        import tempfile

        import can
        from asammdf import MDF
    except ImportError:
        return None
    t = 1757000000.25
    frames = [
        can.Message(timestamp=t, arbitration_id=0x18A, is_extended_id=False, data=bytes.fromhex("7413454E70000000"), channel=1),
        can.Message(timestamp=t + 0.001, arbitration_id=0x70A, is_extended_id=False, data=b"\x05", channel=1),
        can.Message(timestamp=t + 0.002, arbitration_id=0x18DAF110, is_extended_id=True, data=b"\x01\x02", channel=2, is_rx=False),
        can.Message(timestamp=t + 0.003, arbitration_id=0x70A, is_extended_id=False, is_remote_frame=True, dlc=1, channel=1),
        can.Message(timestamp=t + 0.004, arbitration_id=0x7, is_extended_id=False, is_error_frame=True, channel=1),
        can.Message(timestamp=t + 0.005, arbitration_id=0x58A, is_extended_id=False, data=bytes.fromhex("4B17100009000000"), channel=1),
    ]
    seeds = []
    with tempfile.TemporaryDirectory() as tmp:
        for level in (0, 1, 2):
            path = f"{tmp}/{level}.mf4"
            w = can.MF4Writer(path, compression_level=level)
            for m in frames:
                w.on_message_received(m)
            w.stop()
            seeds.append((f"python_can_{level}", bytes([1]) + open(path, "rb").read()))
        with MDF(f"{tmp}/0.mf4") as mdf:
            converted = mdf.convert("4.20")
            converted.configure(write_fragment_size=256)
            converted.save(f"{tmp}/420.mf4", compression=2, overwrite=True)
            converted.close()
        seeds.append(("asammdf_420_fragments", bytes([1]) + open(f"{tmp}/420.mf4", "rb").read()))
        seeds.append(("python_can_0_copying", bytes([0]) + seeds[0][1][1:]))
    return seeds


def socketcan(word, data, fd_flags=0, size=16):
    p = struct.pack(">I", word) + bytes([len(data), fd_flags, 0, 0]) + data
    return p + bytes(max(0, size - len(p)))


def pcap_file(order, magic, link, packets):
    f = struct.pack(order + "IHHiIII", magic, 2, 4, 0, 0, 65535, link)
    for sec, frac, data in packets:
        f += struct.pack(order + "IIII", sec, frac, len(data), len(data)) + data
    return f


def ng_block(order, block_type, body):
    body += bytes(-len(body) % 4)
    n = 12 + len(body)
    return struct.pack(order + "II", block_type, n) + body + struct.pack(order + "I", n)


def pcapng_file(order):
    f = ng_block(order, 0x0A0D0D0A, struct.pack(order + "IHHq", 0x1A2B3C4D, 1, 0, -1))
    opts = struct.pack(order + "HH", 9, 1) + bytes([9, 0, 0, 0]) + struct.pack(order + "HHq", 14, 8, 2) + bytes(4)
    f += ng_block(order, 1, struct.pack(order + "HHI", 227, 0, 0) + opts)
    f += ng_block(order, 1, struct.pack(order + "HHI", 227, 0, 0))
    f += ng_block(order, 4, bytes(8))
    ts = 1756955646068614123
    for i, (word, data, fd, size) in enumerate([
        (0x70A, b"\x7f", 0, 16),
        (0x8000_0000 | 0x18DAF110, b"\x01\x02", 0, 16),
        (0x4000_0000 | 0x70A, b"", 0, 16),
        (0x123, bytes(range(12)), 4, 72),
        (0x2000_0000 | 0x7FF, bytes(8), 0, 16),
    ]):
        p = socketcan(word, data, fd, size)
        f += ng_block(order, 6, struct.pack(order + "IIIII", i % 2, ts >> 32, ts & 0xFFFFFFFF, len(p), len(p)) + p)
    p = socketcan(0x18A, bytes.fromhex("7413454E70000000"))
    f += ng_block(order, 3, struct.pack(order + "I", len(p)) + p)
    f += ng_block(order, 2, struct.pack(order + "HHIIII", 0, 0, 0, 7, len(p), len(p)) + p)
    return f


def pcap_seeds():
    pkts = [(1756955646, 68614, socketcan(0x70A, b"\x7f")), (1756955647, 1, socketcan(0x123, bytes(12), 4, 72))]
    return [
        ("pcap_le_us", bytes([255, 0]) + pcap_file("<", 0xA1B2C3D4, 227, pkts)),
        ("pcap_be_ns_small_chunks", bytes([0, 0]) + pcap_file(">", 0xA1B23C4D, 227, pkts)),
        ("pcap_ethernet", bytes([255, 0]) + pcap_file("<", 0xA1B2C3D4, 1, [(1, 0, bytes(60))])),
        ("pcapng_le", bytes([255, 0]) + pcapng_file("<")),
        ("pcapng_be_small_chunks", bytes([0, 0]) + pcapng_file(">")),
        ("after_pcap_header", bytes([7, 2]) + struct.pack("<IIII", 1, 2, 16, 16) + socketcan(0x18A, b"\x01")),
    ]


def write(target, seeds):
    out = HERE / "seeds" / target
    out.mkdir(parents=True, exist_ok=True)
    for name, data in seeds:
        (out / name).write_bytes(data)


if __name__ == "__main__":
    write("decode_frame", DECODE_FRAME)
    write("blf", blf_seeds())
    mf4 = mf4_seeds()
    if mf4 is not None:
        write("mf4", mf4)
    write("pcap", pcap_seeds())
    write("asc_line", asc_seeds())
    write("trace_line", trace_line_seeds())
    write("decoder_run", decoder_run_seeds())
    write("eds_parse", eds_parse_seeds())
    write("sdo_wire", [(name, bytes.fromhex(data)) for name, data in SDO_WIRE])
    write("concise_dcf", CONCISE_DCF)
