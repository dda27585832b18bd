//! `canopen-decode` guesses nothing: every CiA 301 communication object is
//! named and explained, Delta-Q names and labels need Delta-Q evidence, a
//! node without a role or EDS gets no profile names, CSV output stays one
//! CSV, an invalid 1200h adds no channel, PDO entries mapped narrower than
//! their objects are read and flagged, TIME frames say their UTC time, and
//! the option list in docs/DECODER.md is the one the program prints.

use crate::decoder_support;

use decoder_support::*;

/// A fresh directory for one test's files.
fn scratch(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "canopen-decode-naming-{name}-{}",
        std::process::id()
    ));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn communication_objects_named_and_explained() {
    // Node 4 has no role: CiA 301 names only.
    let input = "\
604#2B0C1000F4010000\n584#600C100000000000\n\
604#2F0D100003000000\n584#600D100000000000\n\
604#2310100173617665\n584#6010100100000000\n\
604#4011100100000000\n584#4311100101000000\n\
604#2F29100101000000\n584#6029100100000000\n\
604#40801F0000000000\n584#43801F0004000000\n\
604#2F511F0101000000\n584#60511F0100000000\n\
604#40571F0100000000\n584#43571F0107000000\n\
604#40FF100000000000\n584#4FFF100000000000\n\
604#4005100000000000\n584#4305100080000040\n\
604#4001120100000000\n584#4301120104060080\n\
604#4081600000000000\n584#4F816000FF000000\n";
    let o = run(&["-"], Some(input));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(
        transfers(&text(&o)),
        [
            "SDO download 100Ch:00 to node 4: F4 01 (guard time: 500 ms)",
            "SDO download 100Dh:00 to node 4: 03 (life time factor: node life time = 3 x guard time)",
            "SDO download 1010h:01 to node 4: 73 61 76 65 (store parameters: all parameters: signature \"save\": saves now)",
            "SDO upload 1011h:01 from node 4: 01 00 00 00 (restore default parameters: all parameters: restores on command)",
            "SDO download 1029h:01 to node 4: 01 (error behaviour: communication error: no change of state)",
            "SDO upload 1F80h:00 from node 4: 04 00 00 00 (NMT start-up: NMT slave, does not enter operational by itself)",
            "SDO download 1F51h:01 to node 4: 01 (program control 1: start program / program started)",
            "SDO upload 1F57h:01 from node 4: 07 00 00 00 (flash status identification 1: in progress, data format error or checksum error)",
            "SDO upload 10FFh:00 from node 4: 00 (10FFh:00, reserved in the communication profile area)",
            "SDO upload 1005h:00 from node 4: 80 00 00 40 (COB-ID SYNC: 080h, SYNC producer)",
            "SDO upload 1201h:01 from node 4: 04 06 00 80 (SDO server parameter 1: COB-ID client to server: 604h, invalid)",
            // A profile object of a node without a role: bytes only.
            "SDO upload 6081h:00 from node 4: FF",
        ]
    );
    let v = json_transfers(&run(&["--json", "-"], Some(input)));
    assert_eq!(v[0]["name"], "guard time");
    assert_eq!(v[0]["value"], 500);
    assert_eq!(v[1]["name"], "life time factor");
    assert_eq!(v[1]["value"], 3);
    assert!(v[11]["name"].is_null());
}

#[test]
fn delta_q_names_only_with_delta_q_evidence() {
    // Node 10 says it is a CiA 419 charger, then sends an EMCY whose bytes
    // a Delta-Q charger would use for E-0-3-2; then its vendor ID, Delta-Q's.
    let emcy = "08A#3081012080000000\n";
    let input = format!(
        "60A#4000100000000000\n58A#43001000A3010000\n{emcy}\
         60A#4003100100000000\n58A#4303100130818020\n\
         60A#4018100100000000\n58A#4318100110010000\n{emcy}"
    );
    let o = run(&["-"], Some(&input));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = text(&o);
    let lines: Vec<&str> = out.lines().collect();
    assert!(
        out.contains("(device type: CiA 419 battery charger, additional information 0000h)"),
        "{out}"
    );
    assert!(
        out.contains("node 10 is the charger (its device type, 1000h, says so)"),
        "{out}"
    );
    let first = lines
        .iter()
        .position(|l| l.contains("EMCY node 10"))
        .unwrap();
    assert!(
        !lines[first].contains("Delta-Q"),
        "a CiA 419 charger is no Delta-Q charger: {}",
        lines[first]
    );
    let field = transfers(&out)[1].clone();
    assert!(
        !field.contains("Delta-Q"),
        "no Delta-Q code in 1003h without evidence: {field}"
    );
    assert!(
        out.contains("node 10 is a Delta-Q device (its vendor ID, 1018h:01, is 00000110h)"),
        "{out}"
    );
    let last = lines
        .iter()
        .rposition(|l| l.contains("EMCY node 10"))
        .unwrap();
    assert!(
        lines[last].ends_with(", Delta-Q E-0-3-2 heartbeat lost"),
        "{}",
        lines[last]
    );
    // --charger-node is Delta-Q evidence.
    let o = run(&["--charger-node", "10", "-"], Some(emcy));
    assert!(text(&o).contains("Delta-Q E-0-3-2"), "{}", text(&o));
    // JSON: the learned facts on lines of their own.
    let v = json_lines(&run(&["--json", "-"], Some(&input)));
    let facts: Vec<_> = v.iter().filter(|v| v["kind"] == "role").collect();
    assert_eq!(facts.len(), 2);
    assert_eq!(facts[0]["deltaq"], false);
    assert_eq!(facts[1]["deltaq"], true);
    assert_eq!(facts[1]["role"], "charger");
}

#[test]
fn pdo_fields_of_a_node_without_a_role_are_unnamed() {
    let frame = "18A#7413\n";
    let o = run(&["--pdo", "18A=2002:0:16", "-"], Some(frame));
    let out = text(&o);
    assert!(
        out.contains("TPDO0 node 10: 74 13 = 2002h unknown object: raw 1374h (16 bits)"),
        "{out}"
    );
    assert!(!out.contains("charging current"), "{out}");
    let o = run(
        &["--charger-node", "10", "--pdo", "18A=2002:0:16", "-"],
        Some(frame),
    );
    assert!(
        text(&o).contains("= 2002h charging current 19.45 A"),
        "{}",
        text(&o)
    );
    // A CiA 419 charger (learned from 1000h) gets the CiA 419 objects only.
    let input = "60A#4000100000000000\n58A#43001000A3010000\n18A#7413C8\n";
    let o = run(&["--pdo", "18A=2002:0:16,6081:0:8", "-"], Some(input));
    assert!(
        text(&o).contains(
            "= 2002h unknown object: raw 1374h (16 bits); 6081h battery state of charge 200 % (out of range)"
        ),
        "{}",
        text(&o)
    );
}

#[test]
fn csv_output_stays_one_csv() {
    let o = run(
        &["--bundled", "session", "--output", "csv", "--summary"],
        None,
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = text(&o);
    let mut rows = out.lines();
    let header = csv_row(rows.next().unwrap());
    assert_eq!(header[0], "time");
    let mut n = 0;
    for row in rows {
        assert_eq!(csv_row(row).len(), header.len(), "not a CSV row: {row}");
        n += 1;
    }
    assert!(n > 10);
    assert!(!out.contains("summary:"));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("summary:\n  node 1 (battery):"), "{err}");
    // --summary-file takes it instead, in any output form.
    let dir = scratch("summary");
    let file = dir.join("summary.txt");
    let path = file.display().to_string();
    let o = run(
        &[
            "--bundled",
            "session",
            "--output",
            "csv",
            "--summary-file",
            &path,
        ],
        None,
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(!String::from_utf8_lossy(&o.stderr).contains("summary:"));
    assert_eq!(text(&o), out);
    let written = std::fs::read_to_string(&file).unwrap();
    assert!(
        written.starts_with("summary:\n  node 1 (battery):"),
        "{written}"
    );
    let o = run(&["--bundled", "session", "--summary-file", &path], None);
    assert!(!text(&o).contains("summary:"));
    assert!(std::fs::read_to_string(&file)
        .unwrap()
        .starts_with("summary:"));
    // A file that cannot be written is an I/O error.
    let o = run(
        &[
            "--bundled",
            "session",
            "--summary-file",
            "/nonexistent/dir/s.txt",
        ],
        None,
    );
    assert_eq!(o.status.code(), Some(2));
    std::fs::remove_dir_all(&dir).ok();
}

/// A device of our own: its server SDO on 640h/5C0h + node id with bit 31
/// set (not valid, CiA 301 1200h), an UNSIGNED8 (2000h) and an INTEGER8
/// (2001h) that its TPDO0 maps with 4 bits each, as python-canopen can.
const NARROW_EDS: &str = "[FileInfo]\nFileName=narrow.eds\n\n[DeviceInfo]\nVendorName=Us\nProductName=Narrow\n\n\
[MandatoryObjects]\nSupportedObjects=1\n1=0x1000\n\n\
[1000]\nParameterName=Device type\nObjectType=0x7\nDataType=0x0007\nAccessType=ro\nDefaultValue=0x00000191\nPDOMapping=0\n\n\
[OptionalObjects]\nSupportedObjects=5\n1=0x1200\n2=0x1800\n3=0x1A00\n4=0x2000\n5=0x2001\n\n\
[1200]\nParameterName=Server SDO parameter\nObjectType=0x9\nSubNumber=3\n\n\
[1200sub0]\nParameterName=Highest sub-index\nObjectType=0x7\nDataType=0x0005\nAccessType=ro\nDefaultValue=2\nPDOMapping=0\n\n\
[1200sub1]\nParameterName=COB-ID client to server\nObjectType=0x7\nDataType=0x0007\nAccessType=ro\nDefaultValue=$NODEID+0x80000640\nPDOMapping=0\n\n\
[1200sub2]\nParameterName=COB-ID server to client\nObjectType=0x7\nDataType=0x0007\nAccessType=ro\nDefaultValue=$NODEID+0x800005C0\nPDOMapping=0\n\n\
[1800]\nParameterName=TPDO0 communication\nObjectType=0x9\nSubNumber=2\n\n\
[1800sub0]\nParameterName=Highest sub-index\nObjectType=0x7\nDataType=0x0005\nAccessType=ro\nDefaultValue=1\nPDOMapping=0\n\n\
[1800sub1]\nParameterName=COB-ID\nObjectType=0x7\nDataType=0x0007\nAccessType=rw\nDefaultValue=$NODEID+0x180\nPDOMapping=0\n\n\
[1A00]\nParameterName=TPDO0 mapping\nObjectType=0x9\nSubNumber=3\n\n\
[1A00sub0]\nParameterName=Number of entries\nObjectType=0x7\nDataType=0x0005\nAccessType=rw\nDefaultValue=2\nPDOMapping=0\n\n\
[1A00sub1]\nParameterName=Entry 1\nObjectType=0x7\nDataType=0x0007\nAccessType=rw\nDefaultValue=0x20000004\nPDOMapping=0\n\n\
[1A00sub2]\nParameterName=Entry 2\nObjectType=0x7\nDataType=0x0007\nAccessType=rw\nDefaultValue=0x20010004\nPDOMapping=0\n\n\
[2000]\nParameterName=Level\nObjectType=0x7\nDataType=0x0005\nAccessType=ro\nDefaultValue=0\nPDOMapping=1\n\n\
[2001]\nParameterName=Offset\nObjectType=0x7\nDataType=0x0002\nAccessType=ro\nDefaultValue=0\nPDOMapping=1\n";

#[test]
fn invalid_sdo_server_and_narrow_pdo_entries_from_an_eds() {
    let dir = scratch("eds");
    let path = dir.join("narrow.eds");
    std::fs::write(&path, NARROW_EDS).unwrap();
    let arg = format!("3={}", path.display());
    let input = "183#EF\n643#4000100000000000\n";
    let o = run(&["--eds", &arg, "-"], Some(input));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("SDO server parameter 1200h not valid (COB-IDs 80000643h/800005C3h, bit 31 set): no channel"),
        "{err}"
    );
    assert!(!err.contains("SDO on"), "{err}");
    let out = text(&o);
    let lines: Vec<&str> = out.lines().collect();
    // Low nibble first: 0xF is 15 for the UNSIGNED8, 0xE is -2 for the
    // INTEGER8 (sign-extended from 4 bits), each flagged.
    assert!(
        lines[0].ends_with(
            "= [from the EDS] 2000h Level 15 [deviates: mapped as 4 bits, object has 8]; \
             2001h Offset -2 [deviates: mapped as 4 bits, object has 8]"
        ),
        "{}",
        lines[0]
    );
    // 643h stays node 67's default request channel, not node 3's.
    assert!(lines[1].contains("SDO request to node 67"), "{}", lines[1]);
    let v = json_lines(&run(&["--json", "--eds", &arg, "-"], Some(input)));
    let fields = v[0]["fields"].as_array().unwrap();
    assert_eq!(fields[0]["kind"], "narrowed");
    assert_eq!(fields[0]["value"], 15);
    assert_eq!(fields[1]["kind"], "narrowed");
    assert_eq!(fields[1]["value"], -2);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn time_frames_say_their_utc_date_and_time() {
    // 43 200 000 ms after midnight of day 2: 1984-01-03, noon.
    let frame = "100#002E93020200\n";
    let o = run(&["-"], Some(frame));
    assert!(
        text(&o).contains(
            "TIME day 2 since 1984-01-01, 43200000 ms after midnight = 1984-01-03T12:00:00.000Z"
        ),
        "{}",
        text(&o)
    );
    let v = json_lines(&run(&["--json", "-"], Some(frame)));
    assert_eq!(v[0]["days"], 2);
    assert_eq!(v[0]["millis"], 43_200_000);
    assert_eq!(v[0]["utc"], "1984-01-03T12:00:00.000Z");
}

#[test]
fn an_eds_with_delta_qs_vendor_id_is_delta_q_evidence() {
    let dir = scratch("vendor");
    let eds = |vendor: &str| {
        format!(
            "[DeviceInfo]\nVendorName=Someone\nVendorNumber={vendor}\n\n\
             [MandatoryObjects]\nSupportedObjects=1\n1=0x1000\n\n\
             [1000]\nParameterName=Device type\nObjectType=0x7\nDataType=0x0007\n\
             AccessType=ro\nDefaultValue=0x000001A3\nPDOMapping=0\n"
        )
    };
    let emcy = "08A#3081012080000000\n";
    for (vendor, deltaq) in [("0x00000110", true), ("0x00000539", false)] {
        let path = dir.join(format!("{vendor}.eds"));
        std::fs::write(&path, eds(vendor)).unwrap();
        let arg = format!("10={}", path.display());
        let o = run(&["--eds", &arg, "-"], Some(emcy));
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains("device type 000001A3h: the charger"), "{err}");
        assert_eq!(
            err.contains("vendor ID 00000110h: Delta-Q"),
            deltaq,
            "{err}"
        );
        let out = text(&o);
        assert!(out.contains("08A  charger  EMCY node 10"), "{out}");
        assert_eq!(
            out.contains("Delta-Q E-0-3-2 heartbeat lost"),
            deltaq,
            "{out}"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_program_download_reads_as_one() {
    // The master's sequence against the charger, recorded on the simulated
    // bus by tests/devices/program_download.rs (CiA 302-3: stop, clear, the image
    // by block into 1F50h:01, flash status, software identification, start).
    let log = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/program-download.log"
    );
    let o = run(&[log], None);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let seq = transfers(&text(&o));
    let image = seq[2].clone();
    assert!(
        image.starts_with("SDO block download 1F50h:01 to node 10: 64 bytes 57 5C 70 64")
            && image.ends_with("(program data 1) [CRC checked]"),
        "{image}"
    );
    assert_eq!(
        [&seq[..2], &seq[3..]].concat(),
        [
            "SDO download 1F51h:01 to node 10: 00 (program control 1: stop program / program stopped)",
            "SDO download 1F51h:01 to node 10: 03 (program control 1: clear program / no program available)",
            "SDO upload 1F57h:01 from node 10: 00 00 00 00 (flash status identification 1: not in progress, ok)",
            "SDO upload 1F56h:01 from node 10: 55 22 09 B0 (program software identification 1: B0092255h)",
            "SDO download 1F51h:01 to node 10: 01 (program control 1: start program / program started)",
        ]
    );
    // A failed download's flash status, in words.
    let o = run(&["-"], Some("60A#40571F0100000000\n58A#43571F010A000000\n"));
    assert_eq!(
        transfers(&text(&o)),
        ["SDO upload 1F57h:01 from node 10: 0A 00 00 00 (flash status identification 1: not in progress, flash write error)"]
    );
}

/// docs/DECODER.md shows the program's `-h` as it prints it: the copy
/// there is checked, not trusted.
#[test]
fn the_option_list_in_the_docs_is_the_programs() {
    let out = run(&["-h"], None);
    assert!(out.status.success());
    let help = String::from_utf8(out.stdout).unwrap();
    let docs = include_str!("../../docs/DECODER.md");
    let marker = "`canopen-decode -h` (`--help` explains each at more length):\n\n```text\n";
    let start = docs.find(marker).expect("the -h block in docs/DECODER.md") + marker.len();
    let block = &docs[start..start + docs[start..].find("```").unwrap()];
    assert_eq!(
        block, help,
        "docs/DECODER.md's -h block differs from the program's"
    );
}
