//! The `canopen-boot` program: `concise` on a hand-written DCF
//! (its concise DCF, CiA 302-3 section 4, checked byte by byte),
//! `--node-id` for `$NODEID`, the exit status of each failure, and `dcf`
//! configuring an EDS for a node.

use crate::decoder_support::{canopen_boot, scratch};

fn boot(args: &[&str]) -> (i32, Vec<u8>, String) {
    let o = canopen_boot(args).output().unwrap();
    (
        o.status.code().unwrap(),
        o.stdout,
        String::from_utf8(o.stderr).unwrap(),
    )
}

/// Node 3: the heartbeat time (rw, 500), TPDO 1's transmission type (rw,
/// `$NODEID` in a sum), the device type (ro: never written) and a value
/// with a default only (not written).
const DCF: &str = "\
[DeviceComissioning]
NodeID=3

[1000]
ParameterName=Device type
DataType=0x0007
AccessType=ro
ParameterValue=0x00010192

[1017]
ParameterName=Producer heartbeat time
DataType=0x0006
AccessType=rw
ParameterValue=500

[2000]
ParameterName=Limit
DataType=0x0007
AccessType=rw
ParameterValue=$NODEID+0x100

[2001]
ParameterName=Default only
DataType=0x0005
AccessType=rw
DefaultValue=4
";

fn path(p: &std::path::Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn concise_writes_the_configured_values() {
    let dir = scratch("concise");
    let dcf = dir.join("node3.dcf");
    let out = dir.join("node3.bin");
    std::fs::write(&dcf, DCF).unwrap();
    let (code, stdout, stderr) = boot(&["concise", path(&dcf), path(&out)]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stdout.is_empty());
    assert!(stderr.contains("2 entries, 24 bytes"), "{stderr}");
    #[rustfmt::skip]
    let expected: &[u8] = &[
        2, 0, 0, 0,
        0x17, 0x10, 0, 2, 0, 0, 0, 0xF4, 0x01, // 1017h = 500
        0x00, 0x20, 0, 4, 0, 0, 0, 0x03, 0x01, 0, 0, // 2000h = 103h
    ];
    assert_eq!(std::fs::read(&out).unwrap(), expected);

    // One entry: the count in words.
    let one = dir.join("one.dcf");
    std::fs::write(&one, DCF.replace("ParameterValue=$NODEID+0x100", "")).unwrap();
    let (code, _, stderr) = boot(&["concise", path(&one), path(&out)]);
    assert_eq!(code, 0, "{stderr}");
    assert!(stderr.contains("1 entry, 13 bytes"), "{stderr}");

    // Another node id for $NODEID.
    let (code, _, stderr) = boot(&["concise", path(&dcf), path(&out), "--node-id", "0x10"]);
    assert_eq!(code, 0, "{stderr}");
    assert_eq!(&std::fs::read(&out).unwrap()[20..24], &[0x10, 0x01, 0, 0]);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn each_failure_has_its_exit_status() {
    let dir = scratch("failures");
    let out = dir.join("out.bin");
    // A missing DCF: usage error, the path named.
    let missing = dir.join("missing.dcf");
    let (code, _, stderr) = boot(&["concise", path(&missing), path(&out)]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("missing.dcf"), "{stderr}");
    assert!(!out.exists());
    // A value that does not fit its type: the entry named, status 1.
    let bad = dir.join("bad.dcf");
    std::fs::write(
        &bad,
        DCF.replace("ParameterValue=500", "ParameterValue=70000"),
    )
    .unwrap();
    let (code, _, stderr) = boot(&["concise", path(&bad), path(&out)]);
    assert_eq!(code, 1, "{stderr}");
    assert!(stderr.contains("1017h sub 0"), "{stderr}");
    // $NODEID without a NodeID.
    let anonymous = dir.join("anonymous.dcf");
    std::fs::write(&anonymous, DCF.replace("NodeID=3\n", "")).unwrap();
    let (code, _, stderr) = boot(&["concise", path(&anonymous), path(&out)]);
    assert_eq!(code, 1, "{stderr}");
    assert!(stderr.contains("2000h sub 0"), "{stderr}");
    // Not a device description at all.
    let text = dir.join("text.dcf");
    std::fs::write(&text, "[1017\n").unwrap();
    let (code, _, stderr) = boot(&["concise", path(&text), path(&out)]);
    assert_eq!(code, 1, "{stderr}");
    assert!(stderr.contains("line 1"), "{stderr}");
    // An output that cannot be written.
    let good = dir.join("good.dcf");
    std::fs::write(&good, DCF).unwrap();
    let nowhere = dir.join("no/such/folder/out.bin");
    let (code, _, stderr) = boot(&["concise", path(&good), path(&nowhere)]);
    assert_eq!(code, 2, "{stderr}");
    // Usage errors: no subcommand, a bad node id.
    assert_eq!(boot(&[]).0, 2);
    let (code, _, stderr) = boot(&["concise", path(&good), path(&out), "--node-id", "128"]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("not a node id"), "{stderr}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn dcf_configures_an_eds_for_a_node() {
    let dir = scratch("dcf");
    let eds = dir.join("device.eds");
    // The DCF above without its commissioning section and values.
    let text: String = DCF
        .lines()
        .filter(|l| !l.starts_with("ParameterValue") && !l.starts_with("NodeID"))
        .filter(|l| *l != "[DeviceComissioning]")
        .map(|l| format!("{l}\n"))
        .collect();
    std::fs::write(&eds, text).unwrap();
    let out = dir.join("node7.dcf");
    let (code, _, stderr) = boot(&[
        "dcf",
        path(&eds),
        path(&out),
        "--node-id",
        "7",
        "--set",
        "1017=1000",
        "--set",
        "2000h:0h=$NODEID+0x100",
    ]);
    assert_eq!(code, 0, "{stderr}");
    let dcf = canopen_codec::eds::parse(&std::fs::read_to_string(&out).unwrap()).unwrap();
    assert_eq!(dcf.node_id().map(|n| n.raw()), Some(7));
    let values: Vec<(u16, u8, Vec<u8>)> = dcf
        .configured_values()
        .unwrap()
        .into_iter()
        .map(|(a, v)| (a.index, a.sub, v))
        .collect();
    assert_eq!(
        values,
        [
            (0x1017, 0, vec![0xE8, 0x03]),
            (0x2000, 0, vec![0x07, 0x01, 0, 0])
        ]
    );
    // A read-only object: refused, nothing written; a malformed --set:
    // a usage error.
    let refused = dir.join("refused.dcf");
    let (code, _, stderr) = boot(&[
        "dcf",
        path(&eds),
        path(&refused),
        "--node-id",
        "7",
        "--set",
        "1000=1",
    ]);
    assert_eq!(code, 1, "{stderr}");
    assert!(stderr.contains("1000h sub 0: not writable"), "{stderr}");
    assert!(!refused.exists());
    let (code, _, stderr) = boot(&[
        "dcf",
        path(&eds),
        path(&refused),
        "--node-id",
        "7",
        "--set",
        "1017",
    ]);
    assert_eq!(code, 2, "{stderr}");
    assert!(stderr.contains("INDEX[:SUB]=VALUE"), "{stderr}");
    let _ = std::fs::remove_dir_all(&dir);
}
