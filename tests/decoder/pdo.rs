//! `canopen-decode` and PDOs: `--pdo`, the capture's mapping, the defaults
//! of a node with a role, mappings written by SDO in the log, and `--eds`.

use crate::common;
use crate::decoder_support;

use decoder_support::*;
use serde_json::Value;

/// The capture README's mapping, as `--pdo` arguments (padding the README
/// leaves unnamed as CiA 301 dummy entries 0005h / 0006h).
const CAPTURE_PDO_ARGS: [&str; 13] = [
    "--charger-node",
    "10",
    "--battery-node",
    "1",
    "--no-default-pdos",
    "--pdo",
    "18A=2002:0:16,2101:0:16,2006:0:16,6:0:16",
    "--pdo",
    "0x38A=2060:00:32,2200:00:16,6080:00:8,5:0:8",
    "--pdo",
    "20A=2FFA:1:8,6081:0:8,4201:0:8,2276:0:16,6070:0:16,6000:0:8",
    "--pdo",
    "30a=0x2ffa:1:8,2FFA:01:8,2002:0:16,2101:0:16,6010:0:16",
];

#[test]
fn capture_mapping_in_words() {
    let (Some(startup), Some(charging)) = (
        capture(common::captures::STARTUP),
        capture(common::captures::CHARGING),
    ) else {
        return;
    };
    let mut args = CAPTURE_PDO_ARGS.to_vec();
    args.push(&charging);
    let o = run(&args, None);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = text(&o);
    assert_eq!(out.lines().count(), 848);
    // Numbers in words: rounded to at most 2 decimals, trailing zeros dropped.
    for want in [
        "1757032317.008242       18A  charger  TPDO0 node 10: 74 13 45 4E 70 00 00 00 = \
         2002h charging current 19.45 A; 2101h battery voltage 78.27 V; \
         2006h extended charge status: AC present, charger enabled, override external (BMS)",
        "38A  charger  TPDO2 node 10: 00 00 00 00 BA 07 FF 00 = 2060h displayed error: none; \
         2200h AC voltage 123.63 V; 6080h charger state of charge: invalid (raw FFh)",
        "20A  charger  RPDO0 node 10: 00 4C 01 00 52 A0 00 01 = 6081h battery state of charge 76 %; \
         4201h external override: equalize; 2276h voltage request 82 V; \
         6070h charge current requested 10 A; 6000h battery status: ready to charge",
        "30A  charger  RPDO1 node 10: 00 00 00 0A 00 52 30 02 = 2002h charging current 10 A; \
         2101h battery voltage 82 V; 6010h temperature 70 degC",
    ] {
        assert!(out.contains(want), "missing {want}");
    }
    for l in out.lines() {
        let mapped = [" 18A ", " 38A ", " 20A ", " 30A "]
            .iter()
            .any(|id| l.contains(id));
        assert_eq!(l.contains(" = "), mapped, "{l}");
        assert!(!l.contains("default"), "{l}");
    }
    // 0x28A has no published layout: raw, as before.
    assert!(out.contains("28A  charger  TPDO1 node 10: 00 00 00 00 00 00 00 00\n"));

    // --pdo-capture-mapping is the same thing in one flag.
    let short = run(&["--pdo-capture-mapping", &charging], None);
    assert_eq!(text(&short), out);

    // The startup capture's BMS reports no current yet.
    let startup = text(&run(&["--pdo-capture-mapping", &startup], None));
    assert!(startup.contains(
        "30A  charger  RPDO1 node 10: 00 00 00 00 00 4E 30 02 = 2002h charging current 0 A; \
         2101h battery voltage 78 V; 6010h temperature 70 degC"
    ));
}

#[test]
fn capture_mapping_in_json() {
    let Some(charging) = capture(common::captures::CHARGING) else {
        return;
    };
    let o = run(&["--json", "--pdo-capture-mapping", &charging], None);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let values: Vec<Value> = text(&o)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let mut seen = std::collections::BTreeSet::new();
    for v in &values {
        let id = v["id"].as_u64().unwrap();
        let mapped = matches!(id, 0x18A | 0x38A | 0x20A | 0x30A);
        assert_eq!(v["fields"].is_array(), mapped, "{v}");
        if !mapped {
            continue;
        }
        assert_eq!(v["mapping"], "given");
        assert_eq!(v["unmapped_bytes"], 0);
        for f in v["fields"].as_array().unwrap() {
            for k in [
                "index", "sub", "bits", "name", "raw", "kind", "value", "text",
            ] {
                assert!(f.get(k).is_some(), "{k} in {f}");
            }
            assert_eq!(
                f["kind"] == "scaled",
                f["value"].is_f64() || f["value"].is_u64()
            );
            assert_eq!(f.get("unit").is_some(), f["kind"] == "scaled", "{f}");
        }
        seen.insert((id, v["data"].as_str().unwrap().to_string()));
        let fields = v["fields"].as_array().unwrap();
        let field = |i: usize| &fields[i];
        match (id, v["data"].as_str().unwrap()) {
            (0x18A, "7413454e70000000") => {
                assert_eq!(field(0)["index"], 0x2002);
                assert_eq!(field(0)["name"], "charging current");
                assert_eq!(field(0)["raw"], 0x1374);
                assert_eq!(field(0)["value"], 19.453125); // exact in JSON
                assert_eq!(field(0)["unit"], "A");
                assert_eq!(field(1)["index"], 0x2101);
                assert_eq!(field(1)["value"], 78.26953125);
                assert_eq!(field(1)["unit"], "V");
                assert_eq!(field(2)["index"], 0x2006);
                assert_eq!(field(2)["raw"], 0x70);
                assert_eq!(field(2)["kind"], "flags");
                assert_eq!(
                    field(2)["value"],
                    "AC present, charger enabled, override external (BMS)"
                );
                assert_eq!(field(3)["kind"], "padding");
                assert_eq!(field(3)["index"], 6);
            }
            (0x38A, "00000000ba07ff00") => {
                assert_eq!(field(0)["index"], 0x2060);
                assert_eq!(field(0)["kind"], "error");
                assert_eq!(field(0)["value"], "none");
                assert_eq!(field(1)["value"], 123.625);
                assert_eq!(field(1)["unit"], "V");
                assert_eq!(field(2)["index"], 0x6080);
                assert_eq!(field(2)["raw"], 255);
                assert_eq!(field(2)["kind"], "invalid");
                assert!(field(2)["value"].is_null());
            }
            (0x20A, "004c010052a00001") => {
                assert_eq!(field(0)["index"], 0x2FFA);
                assert_eq!(field(0)["sub"], 1);
                assert_eq!(field(1)["name"], "battery state of charge");
                assert_eq!(field(1)["value"], 76);
                assert_eq!(field(1)["unit"], "%");
                assert_eq!(field(2)["value"], "equalize");
                assert_eq!(field(3)["index"], 0x2276);
                assert_eq!(field(3)["value"], 82);
                assert_eq!(field(4)["index"], 0x6070);
                assert_eq!(field(4)["value"], 10);
                assert_eq!(field(4)["unit"], "A");
                assert_eq!(field(5)["value"], "ready to charge");
            }
            (0x30A, "0000000a00523002") => {
                assert_eq!(field(2)["value"], 10);
                assert_eq!(field(3)["value"], 82);
                assert_eq!(field(4)["name"], "temperature");
                assert_eq!(field(4)["raw"], 0x230);
                assert_eq!(field(4)["value"], 70);
                assert_eq!(field(4)["unit"], "degC");
            }
            _ => {}
        }
    }
    for (id, data) in [
        (0x18A, "7413454e70000000"),
        (0x38A, "00000000ba07ff00"),
        (0x20A, "004c010052a00001"),
        (0x30A, "0000000a00523002"),
    ] {
        assert!(seen.contains(&(id, data.to_string())), "{id:x} {data}");
    }
}

#[test]
fn default_mappings_apply_without_pdo() {
    // Charger TPDO 3 (2002h, 2100h Q10, 2006h), charger RPDO 0 (6010h,
    // 6000h), battery TPDO 0 (the same, CiA 418), charger RPDO 3 (no
    // published mapping: raw), another node (no mapping: raw).
    let input = "48A#7413003070000000\n20A#300201\n181#C0FE00\n50A#01\n182#01\n";
    let o = run(
        &["--charger-node", "10", "--battery-node", "1", "-"],
        Some(input),
    );
    assert!(o.status.success());
    let out = text(&o);
    let lines: Vec<&str> = out.lines().collect();
    assert!(
        lines[0].ends_with(
            "= [charger default] 2002h charging current 19.45 A; \
             2100h battery voltage (legacy) 12 V; \
             2006h extended charge status: AC present, charger enabled, override external (BMS) \
             (+2 unmapped bytes)"
        ),
        "{out}"
    );
    assert!(
        lines[1].ends_with(
            "= [charger default] 6010h temperature 70 degC; 6000h battery status: ready to charge"
        ),
        "{out}"
    );
    assert!(
        lines[2].ends_with(
            "= [battery default] 6010h temperature -40 degC; \
             6000h battery status: not ready to charge"
        ),
        "{out}"
    );
    assert!(!lines[3].contains(" = "), "{out}");
    assert!(!lines[4].contains(" = "), "{out}");

    let o = run(
        &["--charger-node", "10", "--battery-node", "1", "--json", "-"],
        Some(input),
    );
    let v: Vec<Value> = text(&o)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(v[0]["mapping"], "charger default");
    assert_eq!(v[0]["unmapped_bytes"], 2);
    assert_eq!(v[0]["fields"][1]["value"], 12);
    assert_eq!(v[2]["mapping"], "battery default");
    assert_eq!(v[2]["fields"][0]["value"], -40);
    assert!(v[3].get("fields").is_none());

    // --no-default-pdos: everything raw.
    let o = run(
        &[
            "--charger-node",
            "10",
            "--battery-node",
            "1",
            "--no-default-pdos",
            "-",
        ],
        Some(input),
    );
    assert!(!text(&o).contains(" = "));

    // A given mapping on the battery node reads CiA 418 objects only; a
    // short frame marks the missing field.
    let o = run(
        &[
            "--charger-node",
            "10",
            "--battery-node",
            "1",
            "--pdo=181=2002:0:16,6081:0:8",
            "-",
        ],
        Some("181#7413\n"),
    );
    assert!(
        text(&o).contains(
            "= 2002h unknown object: raw 1374h (16 bits); \
             6081h battery state of charge: missing (past the end of the frame)"
        ),
        "{}",
        text(&o)
    );
}

#[test]
fn bad_pdo_values_exit_2() {
    for (args, why) in [
        (&["--pdo"][..], "a value is required for '--pdo"),
        (&["--pdo", "18A"], "expected COBID=INDEX:SUB:BITS"),
        (&["--pdo", "18A="], "is not INDEX:SUB:BITS"),
        (&["--pdo", "18A=2002:0"], "is not INDEX:SUB:BITS"),
        (&["--pdo", "18A=2002:0:16:1"], "is not INDEX:SUB:BITS"),
        (
            &["--pdo", "800=2002:0:16"],
            "COB-ID '800' is not hex 0..=7FF",
        ),
        (&["--pdo", "XYZ=2002:0:16"], "COB-ID 'XYZ'"),
        (&["--pdo", "18A=20021:0:16"], "index '20021'"),
        (&["--pdo", "18A=2002:100:16"], "sub-index '100'"),
        (
            &["--pdo", "18A=2002:0:0"],
            "bits '0' is not a decimal 1..=64",
        ),
        (&["--pdo", "18A=2002:0:65"], "bits '65'"),
        (&["--pdo", "18A=2002:0:0x10"], "bits '0x10'"),
        (
            &["--pdo", "18A=6060:0:32,6060:0:32,6001:0:8"],
            "mapping of 72 bits, at most 64",
        ),
        (
            &[
                "--pdo",
                "18A=5:0:8,5:0:8,5:0:8,5:0:8,5:0:8,5:0:8,5:0:8,5:0:8,5:0:8",
            ],
            "9 entries, at most 8",
        ),
        (
            &["--pdo", "18A=6001:0:8", "--pdo", "0x18a=6001:0:8"],
            "COB-ID 18A given twice",
        ),
    ] {
        let o = run(args, None);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains(why), "{args:?}: {err}");
        // clap's errors point to --help; the program's own show the usage.
        assert!(
            err.contains("Usage: canopen-decode") || err.contains("try '--help'"),
            "{err}"
        );
    }
}

#[test]
fn pdo_mappings_written_by_sdo_apply_to_the_pdos_that_follow() {
    // Node 5 (no role): TPDO 1 (1801h/1A01h) remapped by the CiA 301
    // procedure (0 entries, the entries, then their number), then moved to
    // 2A5h; its frames decode by the mapping from then on.
    let input = "\
285#1122334455\n\
605#2F011A0000000000\n585#60011A0000000000\n\
605#23011A0108000060\n585#60011A0100000000\n\
605#23011A0210001060\n585#60011A0200000000\n\
605#2F011A0002000000\n585#60011A0000000000\n\
285#2A3412\n\
605#23011801A5020000\n585#6001180100000000\n\
2A5#2B7856\n";
    let o = run(&["-"], Some(input));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = text(&o);
    let lines: Vec<&str> = out.lines().collect();
    // Before the remap the frame is raw.
    assert!(
        lines[0].ends_with("TPDO1 node 5: 11 22 33 44 55"),
        "{}",
        lines[0]
    );
    let remap = lines
        .iter()
        .find(|l| l.contains("SDO download 1A01h:00") && l.contains("02"))
        .unwrap();
    assert!(
        remap.ends_with(
            "[TPDO1 of node 5 maps 6000h:00/8, 6010h:00/16; applied to the frames on 285h that follow]"
        ),
        "{remap}"
    );
    let pdo = lines
        .iter()
        .find(|l| l.contains("  285  ") && l.contains("2A 34 12"))
        .unwrap();
    assert!(pdo.contains("[from SDO in the log]"), "{pdo}");
    assert!(
        pdo.contains("6000h unknown object: raw 2Ah")
            && pdo.contains("6010h unknown object: raw 1234h"),
        "{pdo}"
    );
    let moved = lines
        .iter()
        .find(|l| l.contains("SDO download 1801h:01"))
        .unwrap();
    assert!(
        moved.ends_with("[TPDO1 of node 5 now on 2A5h; its mapping applies there]"),
        "{moved}"
    );
    let last = lines.last().unwrap();
    assert!(last.contains("[from SDO in the log]"), "{last}");
    // In JSON the transfer carries the note and the PDO its fields.
    let v = json_lines(&run(&["--json", "-"], Some(input)));
    let notes: Vec<&str> = v.iter().filter_map(|x| x["pdo_config"].as_str()).collect();
    assert_eq!(notes.len(), 3, "{notes:?}");
    assert_eq!(notes[0], "TPDO1 of node 5: mapping cleared (0 entries)");
    assert!(notes[1].starts_with("TPDO1 of node 5 maps"), "{}", notes[1]);
    let fields = v.last().unwrap()["fields"].as_array().unwrap().len();
    assert_eq!(fields, 2);
}

/// A small device description of our own, for `--eds`: a pump controller
/// (CiA 401 device type) whose TPDO0 carries its speed (2000h sub 0,
/// UNSIGNED16) and temperature (2001h, INTEGER8), and whose SDO server is
/// not on the default COB-IDs: 640h/5C0h + $NODEID (643h/5C3h for node 3).
const PUMP_EDS: &str = "[FileInfo]\nFileName=pump.eds\n\n[DeviceInfo]\nVendorName=Us\nProductName=Pump\n\n\
[MandatoryObjects]\nSupportedObjects=1\n1=0x1000\n\n\
[1000]\nParameterName=Device type\nObjectType=0x7\nDataType=0x0007\nAccessType=ro\nDefaultValue=0x00000191\nPDOMapping=0\n\n\
[OptionalObjects]\nSupportedObjects=4\n1=0x1200\n2=0x1800\n3=0x1A00\n4=0x2000\n\n\
[1200]\nParameterName=Server SDO parameter\nObjectType=0x9\nSubNumber=3\n\n\
[1200sub0]\nParameterName=Highest sub-index\nObjectType=0x7\nDataType=0x0005\nAccessType=ro\nDefaultValue=2\nPDOMapping=0\n\n\
[1200sub1]\nParameterName=COB-ID client to server\nObjectType=0x7\nDataType=0x0007\nAccessType=ro\nDefaultValue=$NODEID+0x640\nPDOMapping=0\n\n\
[1200sub2]\nParameterName=COB-ID server to client\nObjectType=0x7\nDataType=0x0007\nAccessType=ro\nDefaultValue=$NODEID+0x5C0\nPDOMapping=0\n\n\
[1800]\nParameterName=TPDO0 communication\nObjectType=0x9\nSubNumber=2\n\n\
[1800sub0]\nParameterName=Highest sub-index\nObjectType=0x7\nDataType=0x0005\nAccessType=ro\nDefaultValue=1\nPDOMapping=0\n\n\
[1800sub1]\nParameterName=COB-ID\nObjectType=0x7\nDataType=0x0007\nAccessType=rw\nDefaultValue=$NODEID+0x180\nPDOMapping=0\n\n\
[1A00]\nParameterName=TPDO0 mapping\nObjectType=0x9\nSubNumber=3\n\n\
[1A00sub0]\nParameterName=Number of entries\nObjectType=0x7\nDataType=0x0005\nAccessType=rw\nDefaultValue=2\nPDOMapping=0\n\n\
[1A00sub1]\nParameterName=Entry 1\nObjectType=0x7\nDataType=0x0007\nAccessType=rw\nDefaultValue=0x20000010\nPDOMapping=0\n\n\
[1A00sub2]\nParameterName=Entry 2\nObjectType=0x7\nDataType=0x0007\nAccessType=rw\nDefaultValue=0x20010008\nPDOMapping=0\n\n\
[2000]\nParameterName=Pump\nObjectType=0x9\nSubNumber=2\n\n\
[2000sub0]\nParameterName=Speed\nObjectType=0x7\nDataType=0x0006\nAccessType=ro\nDefaultValue=0\nPDOMapping=1\n\n\
[2000sub1]\nParameterName=Unused\nObjectType=0x7\nDataType=0x0006\nAccessType=ro\nDefaultValue=0\nPDOMapping=1\n\n\
[2001]\nParameterName=Temperature\nObjectType=0x7\nDataType=0x0002\nAccessType=ro\nDefaultValue=0\nPDOMapping=1\n";

#[test]
fn eds_gives_pdo_mappings_sdo_channels_and_names() {
    let dir = std::env::temp_dir().join(format!("canopen-decode-eds-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("pump.eds");
    std::fs::write(&path, PUMP_EDS).unwrap();
    let arg = format!("3={}", path.display());
    let input = "183#3412F6\n643#4001200000000000\n5C3#4F012000F6000000\n";
    let o = run(&["--eds", &arg, "-"], Some(input));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("node 3 from"), "{err}");
    assert!(err.contains("device type 00000191h (profile 401)"), "{err}");
    assert!(err.contains("PDOs mapped: TPDO0 on 183h"), "{err}");
    assert!(err.contains("SDO on 643h/5C3h"), "{err}");
    let out = text(&o);
    let lines: Vec<&str> = out.lines().collect();
    assert!(
        lines[0].ends_with("= [from the EDS] 2000h Pump: Speed 4660; 2001h Temperature -10"),
        "{}",
        lines[0]
    );
    assert!(
        lines[1].contains("SDO request to node 3: initiate upload 2001h sub 0"),
        "{}",
        lines[1]
    );
    // The EDS names the node's objects on the transfer lines too.
    assert_eq!(
        transfers(&out),
        ["SDO upload 2001h:00 from node 3: F6 (Temperature: -10)"]
    );
    // A file that is not there, or not an EDS, is a usage error.
    let o = run(&["--eds", "3=/nonexistent/pump.eds", "-"], Some(input));
    assert_eq!(o.status.code(), Some(2));
    let o = run(&["--eds", "pump.eds", "-"], Some(input));
    assert_eq!(o.status.code(), Some(2));
    std::fs::remove_dir_all(&dir).ok();
}
