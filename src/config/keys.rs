//! How a section's TOML keys reach the runtime types: [`section_keys!`] writes the `Deserialize`
//! of a section struct from one table of `"key" => field.path` lines, so each key is named once
//! and lands straight in the field of the runtime type it sets (its type, default and
//! validation belong to that type). Unknown keys are refused with the list of known ones; the
//! TOML parser adds the file's line and column to every message, and a bad value's message names
//! its key.

/// Implements `serde::Deserialize` for `$section` (which must implement `Default`): every key of
/// the table is one `"key" => field.path` line; a missing key keeps the default, an unknown one is
/// an error naming it.
macro_rules! section_keys {
    ($section:ty { $($key:literal => $($field:ident).+),+ $(,)? }) => {
        impl<'de> serde::Deserialize<'de> for $section {
            fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                const KEYS: &[&str] = &[$($key),+];
                struct Table;
                impl<'de> serde::de::Visitor<'de> for Table {
                    type Value = $section;
                    fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                        write!(f, "a table with the keys {}", KEYS.join(", "))
                    }
                    fn visit_map<A: serde::de::MapAccess<'de>>(self, mut map: A) -> Result<$section, A::Error> {
                        let mut section = <$section>::default();
                        while let Some(key) = map.next_key_seed($crate::config::keys::Key(KEYS))? {
                            match key {
                                $($key => section.$($field).+ = map.next_value()?,)+
                                _ => unreachable!("Key admits only KEYS"),
                            }
                        }
                        Ok(section)
                    }
                }
                d.deserialize_struct(stringify!($section), KEYS, Table)
            }
        }
    };
}
pub(crate) use section_keys;

/// A key of a section, refused unless it is one of the listed ones (the refusal is raised while
/// the key is read, so the parser points at the key).
pub(crate) struct Key(pub &'static [&'static str]);

impl<'de> serde::de::DeserializeSeed<'de> for Key {
    type Value = &'static str;

    fn deserialize<D: serde::Deserializer<'de>>(self, d: D) -> Result<&'static str, D::Error> {
        d.deserialize_identifier(self)
    }
}

impl<'de> serde::de::Visitor<'de> for Key {
    type Value = &'static str;

    fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("a key")
    }

    fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<&'static str, E> {
        self.0.iter().copied().find(|k| *k == v).ok_or_else(|| E::unknown_field(v, self.0))
    }
}

/// Reads a mode given by name (`key = "name"`) as one of `modes`; another name is refused with
/// a message naming the key and the names it takes.
pub(crate) fn by_name<'de, D: serde::Deserializer<'de>, T: Copy>(
    d: D,
    key: &str,
    modes: &[(&str, T)],
) -> Result<T, D::Error> {
    let name = <String as serde::Deserialize>::deserialize(d)?;
    modes.iter().find(|(n, _)| *n == name).map(|(_, m)| *m).ok_or_else(|| {
        let names: Vec<String> = modes.iter().map(|(n, _)| format!("{n:?}")).collect();
        serde::de::Error::custom(format!("{key}: {name:?} is neither {}", names.join(" nor ")))
    })
}
