//! [`fixed_objects!`](crate::fixed_objects): an area's object table and
//! the struct that holds its values, declared once.

/// Declares an area's object table ([`ObjectRow`](crate::od::ObjectRow)s)
/// and the struct that stores its values, one line per object, and serves
/// them as a [`FixedObjects`](crate::od::FixedObjects) dictionary (so
/// [`FixedDictionary`](crate::od::FixedDictionary) answers SDO).
///
/// Each `field: type = row,` line declares a public field of an integer
/// type (`u8`, `u16`, `u32`, `i8`, `i16`, `i32`: the row's data type's
/// size) and its row; the `without_field` rows are entries with no
/// storage (padding: they read their default and drop what is written).
/// Generated, all found by address from the rows:
///
/// - the struct, with `new()` (a `const fn`) giving every field its row's
///   default, and `Default`;
/// - the table `TABLE` (`&[ObjectRow]`: the field rows, then the others),
///   from which the EDS and the PDO catalogue are derived;
/// - the parameters NMT reset node restores, `PARAMETERS` (the writable
///   entries, [`ObjectRow::is_parameter`](crate::od::ObjectRow::is_parameter)),
///   and the type of their power-on values, `POWER_ON` (`[u8; N]`);
/// - the [`FixedObjects`](crate::od::FixedObjects) implementation:
///   `entry` from the row (06020000h / 06090011h for what the table
///   lacks), `store` into the field. They read a compact copy of each
///   row's access, size, mapping and default: the names and readings stay
///   out of a firmware that does not use the table itself.
///
/// ```
/// use canopen_codec::od::{Access, DataType, FixedDictionary, ObjectDictionary, ObjectRow};
/// use canopen_codec::sdo::AbortCode;
///
/// canopen_codec::fixed_objects! {
///     /// A setpoint the bus writes and a reading.
///     pub struct Objects;
///     /// Its table.
///     pub const TABLE;
///     /// What reset node restores.
///     pub const PARAMETERS;
///     /// Their values at boot.
///     pub type POWER_ON = PowerOn;
///     fields {
///         /// 2000h setpoint (rw, default 500).
///         setpoint: u16 = ObjectRow::var(0x2000, "Setpoint", DataType::Unsigned16, Access::ReadWrite)
///             .mappable()
///             .default(500),
///         /// 2001h reading (ro).
///         reading: i8 = ObjectRow::var(0x2001, "Reading", DataType::Integer8, Access::ReadOnly),
///     }
///     without_field {}
/// }
///
/// let mut od = FixedDictionary::new(Objects::new());
/// assert_eq!((od.setpoint, TABLE.len(), PARAMETERS), (500, 2, [(0x2000, 0)]));
/// let at_boot: PowerOn = od.parameters();
/// od.write(0x2000, 0, 0, &[0xE8, 0x03]).unwrap();
/// od.finish_write(0x2000, 0, 2).unwrap();
/// od.reading = -7; // the application's
/// let mut buf = [0u8; 1];
/// assert_eq!((od.setpoint, od.read(0x2001, 0, 0, &mut buf)), (1000, Ok(1)));
/// assert_eq!(buf, [0xF9]);
/// assert_eq!(od.info(0x2001, 1), Err(AbortCode::SubIndexDoesNotExist));
/// assert_eq!(od.info(0x2002, 0), Err(AbortCode::ObjectDoesNotExist));
/// od.restore_parameters(&at_boot); // NMT reset node
/// assert_eq!((od.setpoint, od.reading), (500, -7));
/// ```
#[macro_export]
macro_rules! fixed_objects {
    (
        $(#[$smeta:meta])*
        $svis:vis struct $name:ident;
        $(#[$tmeta:meta])*
        $tvis:vis const $table:ident;
        $(#[$pmeta:meta])*
        $pvis:vis const $params:ident;
        $(#[$vmeta:meta])*
        $vvis:vis type POWER_ON = $power_on:ident;
        fields {
            $(
                $(#[$fmeta:meta])*
                $field:ident: $ty:ty = $row:expr,
            )*
        }
        without_field {
            $($free:expr,)*
        }
    ) => {
        $(#[$smeta])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq)]
        $svis struct $name {
            $(
                $(#[$fmeta])*
                pub $field: $ty,
            )*
        }

        $(#[$tmeta])*
        $tvis const $table: &[$crate::od::ObjectRow] = &[$($row,)* $($free,)*];

        $(#[$pmeta])*
        $pvis const $params: [(u16, u8); $crate::od::ObjectRow::parameter_count($table)] =
            $crate::od::ObjectRow::parameters($table);

        $(#[$vmeta])*
        $vvis type $power_on = [u8; $crate::od::ObjectRow::parameter_bytes($table)];

        impl $name {
            /// The power-on values: every field its row's default.
            #[must_use]
            #[allow(clippy::cast_possible_truncation, clippy::cast_possible_wrap)]
            pub const fn new() -> Self {
                // The default word's low bytes, as the field's type (its
                // row's size): `as` keeps exactly those.
                $name { $($field: { const ROW: $crate::od::ObjectRow = $row; ROW.default as $ty },)* }
            }
        }

        impl Default for $name {
            fn default() -> Self {
                Self::new()
            }
        }

        // The fields' numbers, the entries the dictionary serves and the
        // access to the fields, private to this block.
        const _: () = {
            /// The fields, numbered in declaration order: the
            /// [`FixedEntry::slot`]($crate::od::FixedEntry::slot) of
            /// their entries.
            #[allow(non_camel_case_types, dead_code)]
            #[derive(Clone, Copy)]
            enum Field {
                $($field,)*
            }

            /// The slot of an entry without a field.
            const NO_FIELD: u8 = u8::MAX;

            /// An entry as the dictionary serves it: its object, its
            /// sub-indexes, access, size and PDO mapping.
            type Compact = (u16, u8, u8, $crate::od::Access, u8, bool);

            /// The fields' entries, in field order (a firmware keeps
            /// these, not the rows' names or readings).
            const FIELDS: &[Compact] = &[
                $({
                    const ROW: $crate::od::ObjectRow = $row;
                    // One object per row: no runs of indexes here.
                    const _: () = assert!(ROW.last_index == ROW.address.index);
                    let a = ROW.address;
                    (a.index, a.sub, ROW.last_sub, ROW.access, ROW.size(), ROW.mappable)
                },)*
            ];
            const _: () = assert!(FIELDS.len() < NO_FIELD as usize);

            /// The entries without a field, with their value.
            const FREE: &[(Compact, u32)] = &[
                $({
                    const ROW: $crate::od::ObjectRow = $free;
                    const _: () = assert!(ROW.last_index == ROW.address.index);
                    let a = ROW.address;
                    let c = (a.index, a.sub, ROW.last_sub, ROW.access, ROW.size(), ROW.mappable);
                    (c, ROW.default)
                },)*
            ];

            impl $name {
                /// The value of the field in `slot` (0 for none).
                #[allow(clippy::cast_sign_loss)]
                fn field_word(&self, slot: u8) -> u32 {
                    $(
                        if slot == Field::$field as u8 {
                            // A signed value's high bytes are past its
                            // size: only the first `size` bytes are served.
                            return self.$field as u32;
                        }
                    )*
                    0
                }
            }

            impl $crate::od::FixedObjects for $name {
                type Parameters = $power_on;
                const PARAMETERS: &'static [(u16, u8)] = &$params;

                fn entry(
                    &self,
                    index: u16,
                    sub: u8,
                ) -> Result<$crate::od::FixedEntry, $crate::abort::AbortCode> {
                    let mut object = false;
                    let mut slot = 0u8;
                    for &(at, first_sub, last_sub, access, len, mappable) in FIELDS {
                        if at == index {
                            if first_sub <= sub && sub <= last_sub {
                                let word = self.field_word(slot);
                                return Ok($crate::od::FixedEntry {
                                    access,
                                    word,
                                    len,
                                    mappable,
                                    slot,
                                });
                            }
                            object = true;
                        }
                        slot = slot.wrapping_add(1);
                    }
                    for &((at, first_sub, last_sub, access, len, mappable), word) in FREE {
                        if at == index {
                            if first_sub <= sub && sub <= last_sub {
                                return Ok($crate::od::FixedEntry {
                                    access,
                                    word,
                                    len,
                                    mappable,
                                    slot: NO_FIELD,
                                });
                            }
                            object = true;
                        }
                    }
                    Err(if object {
                        $crate::abort::AbortCode::SubIndexDoesNotExist
                    } else {
                        $crate::abort::AbortCode::ObjectDoesNotExist
                    })
                }

                #[allow(clippy::cast_possible_truncation, clippy::cast_possible_wrap)]
                fn store(&mut self, entry: &$crate::od::FixedEntry, _: u16, _: u8, word: u32) {
                    $(
                        {
                            // Only writable entries are stored (the
                            // others are refused before `store`).
                            const WRITABLE: bool = {
                                const ROW: $crate::od::ObjectRow = $row;
                                ROW.access.is_writable()
                            };
                            if WRITABLE && entry.slot == Field::$field as u8 {
                                // The value has no more bytes than the field.
                                self.$field = word as $ty;
                                return;
                            }
                        }
                    )*
                }
            }
        };
    };
}
