//! Arbitrary bytes into the EDS/DCF reader: it never panics; text reads
//! the same through `parse` and `parse_bytes`; whatever parses builds a
//! dictionary of every value it can encode, and the values it leaves out
//! are the ones `unserved` names; its PDOs and names can be asked for; writing it back and reading that gives the same model (line
//! numbers and warnings aside), and writing is then a fixed point.
#![no_main]

use canopen_codec::eds::{parse, parse_bytes, write};
use canopen_codec::NodeId;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(mut eds) = parse_bytes(data) else { return };
    if let Ok(text) = std::str::from_utf8(data) {
        assert_eq!(parse(text).as_ref(), Ok(&eds));
    }
    for node in [NodeId::MIN, NodeId::MAX] {
        let dictionary = eds.dictionary(node);
        assert_eq!(dictionary.unserved(), &eds.unserved(node)[..]);
        let _ = eds.pdos(node);
    }
    for (&index, o) in &eds.objects {
        for &sub in o.subs.keys() {
            assert!(eds.name(index, sub).is_some());
        }
    }
    let text = write(&eds);
    let mut again = parse(&text).expect("written text reads back");
    eds.clear_positions();
    again.clear_positions();
    assert_eq!(again, eds);
    assert_eq!(write(&again), text);
});
