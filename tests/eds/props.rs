//! Property tests of the EDS writer and reader (CiA 306): any description
//! the model can hold is written and read back to the same model, and the
//! text of a written description is a fixed point of write(parse(..)).

use std::collections::BTreeMap;

use canopen_codec::eds::{
    parse, write, AccessType, DataType, Eds, Entry, Keys, Object, ObjectType,
};
use proptest::prelude::*;

fn config() -> ProptestConfig {
    ProptestConfig {
        cases: 256,
        failure_persistence: Some(Box::new(
            proptest::test_runner::FileFailurePersistence::Direct(
                "tests/proptest-regressions/eds_props.txt",
            ),
        )),
        ..ProptestConfig::default()
    }
}

/// Text as a parsed value can be: no line break, no `;` comment, no space
/// at either end.
fn text() -> impl Strategy<Value = String> {
    "([A-Za-z0-9_%+$][A-Za-z0-9 _%+$.-]{0,16}[A-Za-z0-9_%])?"
}

fn access() -> impl Strategy<Value = AccessType> {
    prop_oneof![
        Just(AccessType::ReadOnly),
        Just(AccessType::WriteOnly),
        Just(AccessType::ReadWrite),
        Just(AccessType::ReadWriteRead),
        Just(AccessType::ReadWriteWrite),
        Just(AccessType::Const),
    ]
}

/// Keys the model does not interpret, each once (an `X` prefix keeps them
/// clear of every CiA 306 key).
fn other_keys() -> impl Strategy<Value = Keys> {
    prop::collection::btree_map("X[a-z]{0,6}", text(), 0..3)
        .prop_map(|keys| Keys(keys.into_iter().collect()))
}

fn entry(object_type: ObjectType) -> impl Strategy<Value = Entry> {
    (
        text(),
        prop::option::of(any::<u16>().prop_map(DataType::from)),
        prop::option::of(access()),
        any::<bool>(),
        prop::option::of(text()),
        prop::option::of(text()),
        prop::option::of(prop_oneof![
            any::<i32>().prop_map(|n| n.to_string()),
            any::<u32>().prop_map(|n| format!("0x{n:X}")),
            Just("$NODEID+0x180".to_string()),
        ]),
        prop::option::of(any::<u32>()),
        other_keys(),
    )
        .prop_map(
            move |(name, data_type, access, pdo, default, denotation, limit, flags, other)| Entry {
                name,
                object_type,
                data_type,
                access,
                pdo_mapping: pdo,
                default_value: default,
                denotation,
                low_limit: limit.clone(),
                high_limit: limit,
                obj_flags: flags,
                other,
                ..Entry::default()
            },
        )
}

fn object() -> impl Strategy<Value = Object> {
    prop_oneof![
        entry(ObjectType::Var).prop_map(|e| (e, BTreeMap::new())),
        (
            entry(ObjectType::Record),
            prop::collection::btree_map(any::<u8>(), entry(ObjectType::Var), 1..5)
        ),
    ]
    .prop_map(|(mut entry, subs)| {
        if !subs.is_empty() {
            entry.sub_number = u16::try_from(subs.len()).ok();
        }
        Object {
            index: 0,
            entry,
            subs,
        }
    })
}

fn description() -> impl Strategy<Value = Eds> {
    (
        prop::collection::btree_map(any::<u16>(), object(), 0..12),
        prop::option::of(text()),
        prop::collection::btree_map(1u16..8, any::<bool>(), 0..4),
        prop::collection::vec(text(), 0..3),
    )
        .prop_map(|(objects, file_name, dummy_usage, comments)| {
            let mut eds = Eds::default();
            for (index, mut o) in objects {
                o.index = index;
                match index {
                    0x1000..=0x1FFF => eds.optional.push(index),
                    _ => eds.manufacturer.push(index),
                }
                eds.objects.insert(index, o);
            }
            if let Some(name) = file_name {
                eds.file_info.keys.0.push(("FileName".into(), name.clone()));
                eds.file_info.file_name = Some(name);
            }
            eds.dummy_usage = dummy_usage;
            eds.comments = comments;
            eds
        })
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn written_descriptions_read_back_the_same(eds in description()) {
        let text = write(&eds);
        let mut again = parse(&text).map_err(|e| TestCaseError::fail(format!("{e}\n{text}")))?;
        prop_assert!(
            again.warnings.iter().all(|w| matches!(
                w.kind,
                canopen_codec::eds::WarningKind::InvalidLimit
            )),
            "{:?}", again.warnings
        );
        again.clear_positions();
        prop_assert_eq!(&again, &eds);
        prop_assert_eq!(write(&again), text);
    }
}
