//! `canopen-decode --dbc FILE.dbc`: the DBC read back by a small reader of
//! its own here (`BO_` / `SG_` lines, Intel byte order), every PDO frame of
//! the log decoded with it, and each value compared with `--json`'s.

use crate::common;
use crate::decoder_support;

use std::collections::HashMap;
use std::path::PathBuf;

use decoder_support::*;
use serde_json::Value;

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("canopen-dbc-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// One `SG_` line.
#[derive(Debug)]
struct Sg {
    name: String,
    start: u32,
    len: u32,
    signed: bool,
    scale: f64,
    offset: f64,
    unit: String,
}

/// Messages by identifier: their length and signals.
fn read_dbc(text: &str) -> HashMap<u64, (usize, Vec<Sg>)> {
    let mut out: HashMap<u64, (usize, Vec<Sg>)> = HashMap::new();
    let mut current = None;
    for line in text.lines() {
        if let Some(rest) = line.strip_prefix("BO_ ") {
            let parts: Vec<&str> = rest.split_whitespace().collect();
            let id: u64 = parts[0].parse().unwrap();
            let dlc: usize = parts[2].parse().unwrap();
            out.insert(id, (dlc, Vec::new()));
            current = Some(id);
        } else if let Some(rest) = line.strip_prefix(" SG_ ") {
            // name : start|len@1+ (scale,offset) [min|max] "unit" receiver
            let (name, rest) = rest.split_once(" : ").unwrap();
            let (layout, rest) = rest.split_once(' ').unwrap();
            let (start, bits) = layout.split_once('|').unwrap();
            let (len, order) = bits.split_once('@').unwrap();
            assert!(order.starts_with('1'), "Intel byte order: {line}");
            let (factors, rest) = rest.split_once(") ").unwrap();
            let (scale, offset) = factors.trim_start_matches('(').split_once(',').unwrap();
            let unit = rest.split('"').nth(1).unwrap().to_string();
            out.get_mut(&current.unwrap()).unwrap().1.push(Sg {
                name: name.to_string(),
                start: start.parse().unwrap(),
                len: len.parse().unwrap(),
                signed: order.ends_with('-'),
                scale: scale.parse().unwrap(),
                offset: offset.parse().unwrap(),
                unit,
            });
        }
    }
    out
}

/// The value of `sg` in `data`, as a DBC tool computes it.
fn decode(sg: &Sg, data: &[u8]) -> f64 {
    let mut word = [0u8; 8];
    word[..data.len()].copy_from_slice(data);
    let all = u64::from_le_bytes(word);
    let raw = if sg.len == 64 {
        all >> sg.start
    } else {
        (all >> sg.start) & ((1u64 << sg.len) - 1)
    };
    let v = if sg.signed && sg.len < 64 && raw >> (sg.len - 1) == 1 {
        raw as i64 - (1i64 << sg.len)
    } else {
        raw as i64
    };
    v as f64 * sg.scale + sg.offset
}

fn hex_bytes(s: &str) -> Vec<u8> {
    (0..s.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&s[i..i + 2], 16).unwrap())
        .collect()
}

/// Writes the DBC of a run with `args` and checks every PDO frame of the
/// JSON output decodes by it to the JSON values (numbers to the value, bit
/// fields and codes to the raw integer). Returns the DBC and the number of
/// fields compared.
fn check(args: &[&str], name: &str) -> (String, usize) {
    let path = temp(name);
    let arg = path.display().to_string();
    let mut with_dbc = args.to_vec();
    with_dbc.extend(["--dbc", &arg, "--json"]);
    let o = run(&with_dbc, None);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = std::fs::read_to_string(&path).unwrap();
    let dbc = read_dbc(&text);
    let mut compared = 0;
    for frame in json_lines(&o)
        .into_iter()
        .filter(|v| v["fields"].is_array())
    {
        let id = frame["id"].as_u64().unwrap();
        let (dlc, sgs) = dbc
            .get(&id)
            .unwrap_or_else(|| panic!("no message {id:03X}h in\n{text}"));
        let data = hex_bytes(frame["data"].as_str().unwrap());
        let fields: Vec<&Value> = frame["fields"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|f| f["kind"] != "padding")
            .collect();
        assert_eq!(fields.len(), sgs.len(), "{frame}");
        if data.len() < *dlc {
            continue;
        }
        for (f, sg) in fields.iter().zip(sgs) {
            let got = decode(sg, &data);
            match f["value"].as_f64() {
                Some(want) => {
                    assert_eq!(got, want, "{} of {id:03X}h", sg.name);
                    assert_eq!(sg.unit, f["unit"].as_str().unwrap_or(""));
                }
                None => assert_eq!(got, f["raw"].as_f64().unwrap(), "{}", sg.name),
            }
            compared += 1;
        }
    }
    (text, compared)
}

#[test]
fn bundled_session_dbc_decodes_like_the_json() {
    let (text, compared) = check(&["--bundled", "session"], "session.dbc");
    assert!(compared > 0);
    assert!(
        text.contains(" SG_ temperature : 0|16@1- (0.125,0) [-4096|4095.875] \"degC\""),
        "{text}"
    );
    assert!(text.contains("CM_ SG_ 385 temperature \"6010h temperature\";"));
}

#[test]
fn capture_dbc_decodes_every_pdo_like_the_json() {
    for name in [common::captures::STARTUP, common::captures::CHARGING] {
        let Some(path) = capture(name) else {
            continue;
        };
        let (text, compared) = check(&["--pdo-capture-mapping", &path], &format!("{name}.dbc"));
        assert!(compared > 1000, "{compared}");
        // A message per mapped COB-ID; 28Ah has no published mapping.
        for bo in ["BO_ 394 ", "BO_ 906 ", "BO_ 522 ", "BO_ 778 "] {
            assert!(text.contains(bo), "{bo}");
        }
        assert!(!text.contains("BO_ 650 "));
        assert!(text.contains(" SG_ charging_current : 0|16@1+ (0.00390625,0)"));
    }
}

/// A `--pdo` mapping is in the DBC even when the log has no frame on it.
#[test]
fn given_mapping_without_frames_is_in_the_dbc() {
    let (text, compared) = check(
        &["--bundled", "session", "--pdo", "2A5=6000:0:8,6010:0:16"],
        "given.dbc",
    );
    assert!(compared > 0);
    assert!(text.contains("BO_ 677 TPDO1_node37: 3 node37"), "{text}");
    assert!(text.contains(" SG_ obj_6000h_00 : 0|8@1+ (1,0) [0|255] \"\""));
    assert!(text.contains(" SG_ obj_6010h_00 : 8|16@1+ (1,0) [0|65535] \"\""));
}
