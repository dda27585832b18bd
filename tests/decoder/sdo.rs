//! `canopen-decode` and SDO: transfers reassembled by the library's
//! observer (expedited, segmented, block), how they end, and `--sdo`.

use crate::decoder_support;

use decoder_support::*;
use serde_json::Value;

#[test]
fn sdo_and_options_in_json() {
    let input =
        "602#4018100100000000\n582#43181001040000000\n582#4318100104000000\n5FF#8018100111000906\n";
    let o = run(
        &["--json", "--charger-node", "2", "--battery-node", "127"],
        Some(input),
    );
    assert_eq!(o.status.code(), Some(1)); // line 2 has an odd digit count
    let out = text(&o);
    let v: Vec<Value> = out
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    // The three frames, and after the response the transfer it completed.
    assert_eq!(v.len(), 4);
    assert_eq!(v[0]["kind"], "sdo_rx");
    assert_eq!(v[0]["role"], "charger");
    assert_eq!(v[0]["command"], "initiate_upload");
    assert_eq!(v[0]["index"], 0x1018);
    assert!(v[0]["t"].is_null());
    assert_eq!(v[1]["kind"], "sdo_tx");
    assert_eq!(v[1]["bytes"], "04000000");
    assert_eq!(v[2]["kind"], "sdo_transfer");
    assert_eq!(v[2]["role"], "charger");
    assert_eq!(v[2]["value"], 4);
    // An abort with no transfer open on its channel ends nothing.
    assert_eq!(v[3]["role"], "battery");
    assert_eq!(v[3]["abort_code"], 0x0609_0011);
    assert_eq!(v[3]["abort_meaning"], "Sub-index does not exist");
}

#[test]
fn sdo_sample_transfers_in_words() {
    let o = run(&[SDO_SAMPLE], None);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = text(&o);
    // 26 frames, each on its line as before, and 6 transfers.
    assert_eq!(out.lines().count(), 32);
    let lines: Vec<&str> = out.lines().filter(|l| l.contains(" transfer ")).collect();
    assert_eq!(
        lines,
        [
            "1757100000.001350  transfer  -        SDO upload 1018h:01 from node 2: 04 00 00 00 (identity vendor-ID: 00000004h)",
            "1757100000.101350  transfer  -        SDO download 1017h:00 to node 2: A0 0F (producer heartbeat time: 4000 ms)",
            "1757100000.207750  transfer  -        SDO upload 1008h:00 from node 2: 26 bytes \"Tiny Node - Mega Domains !\" (manufacturer device name)",
            "1757100000.304550  transfer  -        SDO download 2000h:00 to node 2: 13 bytes 41 20 6C 6F 6E 67 20 73 74 72 69 6E 67",
            "1757100000.402950  transfer  -        SDO download 2000h:00 to node 2: 0 bytes",
            "1757100000.501350  transfer  -        SDO upload 1018h:01 from node 2 aborted: 06090011h Sub-index does not exist",
        ]
    );
    // Each transfer line follows the frame that ended it.
    let all: Vec<&str> = out.lines().collect();
    for (i, l) in all
        .iter()
        .enumerate()
        .filter(|(_, l)| l.contains(" transfer "))
    {
        assert!(all[i - 1].contains("582  -        SDO response"), "{l}");
        assert_eq!(all[i - 1].get(..17), l.get(..17));
    }
}

#[test]
fn sdo_sample_transfers_in_json() {
    let o = run(&["--json", SDO_SAMPLE], None);
    assert!(o.status.success());
    let all = json_lines(&o);
    assert_eq!(all.len(), 32);
    let t = json_transfers(&o);
    // The timestamp as serde_json reads the decoder's `1757100000.001350`.
    let base = |t: &str, dir: &str, index: u16, sub: u8| {
        serde_json::json!({
            "t": t.parse::<f64>().unwrap(), "kind": "sdo_transfer", "node": 2, "role": null, "direction": dir,
            "index": index, "sub": sub, "status": "complete", "indicated_size": null,
            "block": false, "crc_checked": false,
            "size_indicated": true, "size_mismatch": false, "truncated": false,
            "unit": null, "meaning": null, "value": null, "name": null,
        })
    };
    let with = |mut v: Value, extra: Value| {
        for (k, x) in extra.as_object().unwrap() {
            v[k] = x.clone();
        }
        v
    };
    let want = [
        with(
            base("1757100000.001350", "upload", 0x1018, 1),
            serde_json::json!({"size": 4, "indicated_size": 4, "bytes": "04000000", "name": "identity vendor-ID",
                "value": 4, "meaning": "00000004h",
                "text": "SDO upload 1018h:01 from node 2: 04 00 00 00 (identity vendor-ID: 00000004h)"}),
        ),
        with(
            base("1757100000.101350", "download", 0x1017, 0),
            serde_json::json!({"size": 2, "indicated_size": 2, "bytes": "a00f", "name": "producer heartbeat time",
                "value": 4000, "unit": "ms", "meaning": "4000 ms",
                "text": "SDO download 1017h:00 to node 2: A0 0F (producer heartbeat time: 4000 ms)"}),
        ),
        with(
            base("1757100000.207750", "upload", 0x1008, 0),
            serde_json::json!({"size": 26, "indicated_size": 26,
                "bytes": "54696e79204e6f6465202d204d65676120446f6d61696e732021",
                "name": "manufacturer device name", "value": "Tiny Node - Mega Domains !",
                "text": "SDO upload 1008h:00 from node 2: 26 bytes \"Tiny Node - Mega Domains !\" (manufacturer device name)"}),
        ),
        with(
            base("1757100000.304550", "download", 0x2000, 0),
            serde_json::json!({"size": 13, "indicated_size": 13, "bytes": "41206c6f6e6720737472696e67",
                "text": "SDO download 2000h:00 to node 2: 13 bytes 41 20 6C 6F 6E 67 20 73 74 72 69 6E 67"}),
        ),
        with(
            base("1757100000.402950", "download", 0x2000, 0),
            serde_json::json!({"size": 0, "indicated_size": 0, "bytes": "",
                "text": "SDO download 2000h:00 to node 2: 0 bytes"}),
        ),
        with(
            base("1757100000.501350", "upload", 0x1018, 1),
            serde_json::json!({"status": "aborted", "size": 0, "bytes": "", "name": "identity vendor-ID",
                "abort": {"code": 0x0609_0011, "meaning": "Sub-index does not exist", "by": "server"},
                "text": "SDO upload 1018h:01 from node 2 aborted: 06090011h Sub-index does not exist"}),
        ),
    ];
    assert_eq!(t.len(), want.len());
    for (got, want) in t.iter().zip(&want) {
        assert_eq!(got, want);
    }
}

#[test]
fn sdo_objects_named_by_role() {
    // Battery node 1, charger node 10 (the defaults); node 4 has no role.
    let input = "\
601#2F01600001000000\n581#6001600000000000\n\
601#4000100000000000\n581#43001000A2010900\n\
60A#4001100000000000\n58A#4F01100081000000\n\
60A#4003100100000000\n58A#4303100100908001\n\
604#2300140104020080\n584#6000140100000000\n\
604#23161002F0000100\n584#6016100200000000\n\
601#40001A0100000000\n581#43001A0110000160\n\
601#4030600100000000\n581#4330600141424344\n\
601#4060600000000000\n581#4360600000480100\n\
601#4081600000000000\n581#4F816000FF000000\n\
601#4017100000000000\n581#4317100010270000\n\
602#4000140200000000\n582#42001402FE000000\n";
    let o = run(
        &["--charger-node", "10", "--battery-node", "1", "-"],
        Some(input),
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(
        transfers(&text(&o)),
        [
            "SDO download 6001h:00 to node 1: 01 (charger status: enabled)",
            "SDO upload 1000h:00 from node 1: A2 01 09 00 (device type: CiA 418 battery module, RPDOs 0/1, TPDOs 0/2)",
            "SDO upload 1001h:00 from node 10: 81 (error register: generic, manufacturer)",
            "SDO upload 1003h:01 from node 10: 00 90 80 01 (pre-defined error field: 9000h external error, \
             information 0180h, Delta-Q E-0-0-1 battery high voltage (threshold from the algorithm))",
            "SDO download 1400h:01 to node 4: 04 02 00 80 (RPDO0 communication: COB-ID: 204h, invalid) \
             [RPDO0 of node 4 is not valid (COB-ID bit 31 set)]",
            "SDO download 1016h:02 to node 4: F0 00 01 00 (consumer heartbeat time: node 1, 240 ms)",
            "SDO upload 1A00h:01 from node 1: 10 00 01 60 (TPDO0 mapping: entry 1: 6001h:00/16 charger status)",
            "SDO upload 6030h:01 from node 1: 41 42 43 44 (battery serial number: \"ABCD\")",
            "SDO upload 6060h:00 from node 1: 00 48 01 00 (battery voltage: 82 V)",
            "SDO upload 6081h:00 from node 1: FF (battery state of charge: invalid (raw FFh))",
            "SDO upload 1017h:00 from node 1: 10 27 00 00 (producer heartbeat time: 4 bytes, the object has 2)",
            "SDO upload 1400h:02 from node 2: FE 00 00 00 (RPDO0 communication: transmission type: \
             event-driven (manufacturer-specific)) [size not indicated]",
        ]
    );
    let v = json_transfers(&run(
        &["--charger-node", "10", "--battery-node", "1", "--json", "-"],
        Some(input),
    ));
    assert_eq!(v[0]["role"], "battery");
    assert_eq!(v[0]["value"], "enabled");
    assert_eq!(v[6]["value"], 0x6001_0010);
    assert_eq!(v[7]["value"], "ABCD");
    assert_eq!(v[8]["value"], 82);
    assert_eq!(v[8]["unit"], "V");
    assert!(v[9]["value"].is_null());
    assert!(v[10]["value"].is_null());
    assert_eq!(v[11]["size_indicated"], false);
    assert_eq!(v[11]["value"], 254);
}

const V8_START: &str =
    "602#4008100000000000\n582#410810001A000000\n602#6000000000000000\n582#0054696E79204E6F\n";

#[test]
fn sdo_stray_segments_end_nothing() {
    // Segments and acknowledgements with no transfer open, then V1.
    let input = "582#0054696E79204E6F\n602#6000000000000000\n602#0041206C6F6E6720\n\
582#2000200000000000\n582#15696E7320210000\n602#4018100100000000\n582#4318100104000000\n";
    let o = run(&["-"], Some(input));
    assert!(o.status.success());
    assert_eq!(
        transfers(&text(&o)),
        ["SDO upload 1018h:01 from node 2: 04 00 00 00 (identity vendor-ID: 00000004h)"]
    );
    // A stray segment inside a download breaks it off, once.
    let o = run(
        &["-"],
        Some("602#210020000D000000\n582#6000200000000000\n582#15696E7320210000\n582#15696E7320210000\n"),
    );
    assert_eq!(
        transfers(&text(&o)),
        [
            "SDO download 2000h:00 to node 2 incomplete: the server's upload segment t=1, 5 bytes: \
             69 6E 73 20 21, last breaks CiA 301 (the client should abort with 05040001h \
             Client/server command specifier not valid or unknown), and no abort followed \
             (0 bytes transferred of 13 indicated)"
        ]
    );
}

#[test]
fn sdo_new_initiate_breaks_off_the_transfer() {
    let input = format!("{V8_START}602#4018100100000000\n582#4318100104000000\n");
    let o = run(&["-"], Some(&input));
    assert!(o.status.success());
    let out = text(&o);
    assert_eq!(
        transfers(&out),
        [
            "SDO upload 1008h:00 from node 2 incomplete: new initiate upload 1018h:01 \
             (7 bytes transferred of 26 indicated)",
            "SDO upload 1018h:01 from node 2: 04 00 00 00 (identity vendor-ID: 00000004h)",
        ]
    );
    // The report follows the initiate that broke the transfer off.
    let lines: Vec<&str> = out.lines().collect();
    assert!(lines[4].contains("initiate upload 1018h sub 1"));
    assert!(lines[5].contains("incomplete"));
    let v = json_transfers(&run(&["--json", "-"], Some(&input)));
    assert_eq!(v[0]["status"], "incomplete");
    assert_eq!(v[0]["incomplete"], "new initiate upload 1018h:01");
    assert_eq!(v[0]["bytes"], "54696e79204e6f");
    assert!(v[0]["value"].is_null());
    assert_eq!(v[1]["status"], "complete");
}

#[test]
fn sdo_toggle_error_is_reported_once() {
    // V8 whose second segment repeats toggle 0; the rest is then stray.
    let input = format!(
        "{V8_START}602#7000000000000000\n582#006465202D204D65\n\
602#6000000000000000\n582#00676120446F6D61\n602#7000000000000000\n582#15696E7320210000\n"
    );
    let o = run(&["-"], Some(&input));
    assert!(o.status.success());
    assert_eq!(
        transfers(&text(&o)),
        [
            "SDO upload 1008h:00 from node 2 incomplete: the server's upload segment t=0, 7 bytes: \
             64 65 20 2D 20 4D 65 breaks CiA 301 (the client should abort with 05030000h Toggle \
             bit not alternated), and no abort followed (7 bytes transferred of 26 indicated)"
        ]
    );
    // A client request with the wrong toggle, a download ack with the wrong
    // toggle, and a client abort (V16, index not filled in).
    let input = format!(
        "{V8_START}602#6000000000000000\n\
602#210020000D000000\n582#6000200000000000\n602#0041206C6F6E6720\n582#3000200000000000\n\
602#4008100000000000\n582#410810001A000000\n602#8000000000000405\n"
    );
    assert_eq!(
        transfers(&text(&run(&["-"], Some(&input)))),
        [
            "SDO upload 1008h:00 from node 2 incomplete: the client's upload segment request t=0 \
             breaks CiA 301 (the server should abort with 05030000h Toggle bit not alternated), \
             and no abort followed (7 bytes transferred of 26 indicated)",
            "SDO download 2000h:00 to node 2 incomplete: the server's download segment ack t=1 \
             breaks CiA 301 (the client should abort with 05030000h Toggle bit not alternated), \
             and no abort followed (7 bytes transferred of 13 indicated)",
            "SDO upload 1008h:00 from node 2 aborted by the client: 05040000h SDO protocol timed out",
        ]
    );
}

#[test]
fn sdo_size_mismatch_truncation_and_log_end_are_reported() {
    // V9: more data than indicated (the transfer completes with the
    // indicated size kept and the mismatch named, as python-canopen's
    // client takes it); V10: less; then a transfer the log cuts.
    let input = format!(
        "602#4008100000000000\n582#4108100004000000\n602#6000000000000000\n582#0554696E79200000\n\
602#401B200000000000\n582#411B2000FEFDFCFB\n602#6000000000000000\n582#00B2012002911203\n\
602#7000000000000000\n582#1D192170FEFDFCFB\n{V8_START}"
    );
    let o = run(&["-"], Some(&input));
    assert!(o.status.success());
    assert_eq!(
        transfers(&text(&o)),
        [
            "SDO upload 1008h:00 from node 2: 4 bytes \"Tiny\" (manufacturer device name) \
             [size mismatch: 4 bytes indicated, 5 transferred]",
            "SDO upload 201Bh:00 from node 2: B2 01 20 02 91 12 03 19 \
             [size mismatch: 4227661310 bytes indicated, 8 transferred]",
            "SDO upload 1008h:00 from node 2 incomplete: the log ends (7 bytes transferred of 26 indicated)",
        ]
    );
    let v = json_transfers(&run(&["--json", "-"], Some(&input)));
    assert_eq!(v[0]["size_mismatch"], true);
    assert_eq!(v[0]["indicated_size"], 4);
    assert_eq!(v[0]["size"], 5);
    // Never more bytes than indicated: "Tiny" of "Tiny ".
    assert_eq!(v[0]["status"], "complete");
    assert_eq!(v[0]["truncated"], false);
    assert_eq!(v[0]["bytes"], "54696e79");
    assert_eq!(v[2]["incomplete"], "the log ends");
    assert!(v[2]["t"].is_null()); // the log has no timestamps

    // 70000 bytes: the first 64 KiB are kept, the total is counted.
    let mut big = String::from("602#4000200000000000\n582#4100200070110100\n");
    for i in 0..10_000u32 {
        let t = if i % 2 == 0 { "" } else { "1" };
        let last = i == 9_999;
        let cmd = if t.is_empty() { 0u8 } else { 0x10 } | u8::from(last);
        big.push_str(&format!(
            "602#{}000000000000000\n",
            if t.is_empty() { "6" } else { "7" }
        ));
        big.push_str(&format!("582#{cmd:02X}41414141414141\n"));
    }
    let v = json_transfers(&run(&["--json", "-"], Some(&big)));
    assert_eq!(v.len(), 1);
    assert_eq!(v[0]["status"], "complete");
    assert_eq!(v[0]["size"], 70_000);
    assert_eq!(v[0]["truncated"], true);
    assert_eq!(v[0]["bytes"].as_str().unwrap().len(), 2 * 65_536);
    assert!(v[0]["text"]
        .as_str()
        .unwrap()
        .ends_with("[truncated: the first 65536 of 70000 bytes kept]"));
}

#[test]
fn sdo_block_transfers_are_reassembled_and_their_segments_named() {
    // V17 and V18 (block download and upload, CRC on both), then V1.
    let input = "\
602#C60020001E000000\n582#A40020007F000000\n602#014120726561 6C6C\n602#027920726561 6C6C\n\
602#03792 06C6F6E6720\n602#0473747269 6E672E\n602#852E2E0000000000\n582#A2057F0000000000\n\
602#D545690000000000\n582#A100000000000000\n\
602#A40810007F000000\n582#C60810001A000000\n602#A300000000000000\n582#0154696E79204E6F\n\
582#026465202D204D65\n582#0367612044 6F6D61\n582#8469 6E73202100 00\n602#A2047F0000000000\n\
582#C940E10000000000\n602#A100000000000000\n\
602#4018100100000000\n582#4318100104000000\n";
    let input = input.replace(' ', "");
    let o = run(&["-"], Some(&input));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = text(&o);
    assert_eq!(
        transfers(&out),
        [
            "SDO block download 2000h:00 to node 2: 30 bytes 41 20 72 65 61 6C 6C 79 20 72 65 61 \
             6C 6C 79 20 6C 6F 6E 67 20 73 74 72 69 6E 67 2E 2E 2E [CRC checked]",
            "SDO block upload 1008h:00 from node 2: 26 bytes \"Tiny Node - Mega Domains !\" \
             (manufacturer device name) [CRC checked]",
            "SDO upload 1018h:01 from node 2: 04 00 00 00 (identity vendor-ID: 00000004h)"
        ]
    );
    // Sub-block segments are named as such, not read as commands.
    let lines: Vec<&str> = out.lines().collect();
    assert!(
        lines[2].ends_with("SDO block segment seq 1 to node 2: 41 20 72 65 61 6C 6C"),
        "{}",
        lines[2]
    );
    assert!(
        lines[6].ends_with("SDO block segment seq 5, last to node 2: 2E 2E 00 00 00 00 00"),
        "{}",
        lines[6]
    );
    assert!(
        lines[14].ends_with("SDO block segment seq 1 from node 2: 54 69 6E 79 20 4E 6F"),
        "{}",
        lines[14]
    );
    assert_eq!(out.matches("block segment").count(), 9);
    let v = json_lines(&run(&["--json", "-"], Some(&input)));
    assert_eq!(v[2]["command"], "block segment");
    assert_eq!(v[2]["seqno"], 1);
    assert_eq!(v[2]["last"], false);
    assert_eq!(v[6]["seqno"], 5);
    assert_eq!(v[6]["last"], true);
    assert_eq!(v[6]["segment_data"], "2e2e0000000000");
    let block: Vec<&Value> = v.iter().filter(|x| x["kind"] == "sdo_transfer").collect();
    assert_eq!(block[0]["block"], true);
    assert_eq!(block[0]["crc_checked"], true);
    assert_eq!(block[1]["size"], 26);
}

#[test]
fn sdo_garbage_never_panics() {
    // A deterministic stream of random SDO frames (any length 0..=8) on two
    // channels, with malformed and short frames among them.
    let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut next = || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        x
    };
    let mut input = String::new();
    for _ in 0..20_000 {
        let r = next();
        let id = [0x602, 0x582, 0x603, 0x583][(r & 3) as usize];
        let len = ((r >> 2) % 9) as usize;
        // Bias byte 0 towards real command specifiers and small toggles.
        let mut bytes: Vec<u8> = (0..len).map(|i| (next() >> (i * 3)) as u8).collect();
        if let Some(b) = bytes.first_mut() {
            *b = [
                0x00, 0x10, 0x01, 0x40, 0x41, 0x60, 0x70, 0x20, 0x21, 0x23, 0x30, 0x80, 0x43,
            ][(r >> 8) as usize % 13]
                | (*b & 0x01);
        }
        let hex: String = bytes.iter().map(|b| format!("{b:02X}")).collect();
        input.push_str(&format!("{id:03X}#{hex}\n"));
    }
    for args in [&["-"][..], &["--json", "-"]] {
        let o = run(args, Some(&input));
        let code = o.status.code();
        assert!(
            matches!(code, Some(0) | Some(1)),
            "{code:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        assert!(!String::from_utf8_lossy(&o.stderr).contains("panicked"));
        if args.len() == 2 {
            let v = json_lines(&o);
            assert!(v.len() >= 20_000);
            let transfers = v.iter().filter(|v| v["kind"] == "sdo_transfer").count();
            assert!(transfers > 0);
        }
    }
}

#[test]
fn sdo_channels_on_other_cob_ids_are_declared_with_sdo() {
    // An SDO server on 241h/1C1h (node 65): an expedited upload of 1008h,
    // then a block upload cut off by the end of the log.
    let input = "241#4008100000000000\n1C1#4F08100041000000\n\
241#A40810007F000000\n1C1#C60810001A000000\n241#A300000000000000\n1C1#0154696E79204E6F\n";
    let o = run(&["--sdo", "65=241,1C1", "-"], Some(input));
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = text(&o);
    assert!(
        out.contains("SDO request to node 65: initiate upload 1008h sub 0"),
        "{out}"
    );
    assert!(
        out.contains("SDO block segment seq 1 from node 65: 54 69 6E 79 20 4E 6F"),
        "{out}"
    );
    assert_eq!(
        transfers(&out),
        [
            "SDO upload 1008h:00 from node 65: 1 bytes \"A\" (manufacturer device name)",
            "SDO block upload 1008h:00 from node 65 incomplete: the log ends before \
             the block acknowledgement of 1 segment (7 bytes, not counted) \
             (0 bytes transferred of 26 indicated)",
        ]
    );
    // The open transfer is reported once, in JSON too.
    let v = json_transfers(&run(
        &["--json", "--sdo", "65=0x241,0x1C1", "-"],
        Some(input),
    ));
    assert_eq!(v.len(), 2);
    assert_eq!(v[1]["status"], "incomplete");
    assert_eq!(v[1]["block"], true);
    // Undeclared, the same frames are PDOs.
    let out = text(&run(&["-"], Some(input)));
    assert!(transfers(&out).is_empty());
    assert!(out.contains("RPDO"), "{out}");
    // A malformed declaration is a usage error.
    for bad in [
        "65=241",
        "x=241,1C1",
        "65=241,241",
        "65=zz,1C1",
        "200=241,1C1",
    ] {
        let o = run(&["--sdo", bad, "-"], Some(input));
        assert_eq!(o.status.code(), Some(2), "--sdo {bad}");
    }
}
