//! The scene format as serde sees it: every struct with its field names and every enum
//! with its variant names, read from the `Deserialize` implementations themselves.
//!
//! Entry point: [`scene_schema`]. A tracing deserializer walks [`Scene`]: serde's
//! derived code announces each struct's fields (`deserialize_struct`) and each enum's
//! variants (`deserialize_enum`); the tracer records them, supplies a placeholder value
//! for every field, and walks again with the next unexplored variant until every
//! variant of every enum has been walked. `docs/scene.md` is checked against this list
//! (`tests/docs_scene.rs`), so a field the parser accepts cannot go undocumented.

use std::collections::BTreeMap;

use serde::de::value::{Error, StrDeserializer};
use serde::de::{self, DeserializeSeed, IntoDeserializer, Visitor};
use serde::Deserialize;

use super::Scene;

/// One named type of the scene format.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TypeSchema {
    /// Type name: `Material`, or `Enum::Variant` for the fields of a struct variant.
    pub name: String,
    /// True for an enum (then `members` are its variants), false for a struct.
    pub is_enum: bool,
    /// Field names (as written in RON, after renames) or variant names.
    pub members: Vec<String>,
}

/// Every struct and enum reachable from [`Scene`], sorted by name.
pub fn scene_schema() -> Vec<TypeSchema> {
    let mut state = State::default();
    loop {
        state.seen_this_pass.clear();
        // Placeholders are accepted by every derived visitor; an error would mean a
        // type the tracer cannot walk (caught by the test of this module).
        let _ = Scene::deserialize(Tracer { state: &mut state });
        let next = state.enums.iter().find_map(|(name, variants)| {
            let done = state.explored.get(name).copied().unwrap_or(0);
            (done + 1 < variants.len()).then(|| name.clone())
        });
        match next {
            Some(name) => *state.explored.entry(name).or_insert(0) += 1,
            None => break,
        }
    }
    let mut out: Vec<TypeSchema> = state
        .structs
        .into_iter()
        .map(|(name, members)| TypeSchema {
            name,
            is_enum: false,
            members,
        })
        .chain(state.enums.into_iter().map(|(name, members)| TypeSchema {
            name,
            is_enum: true,
            members,
        }))
        .collect();
    out.sort_by(|a, b| a.name.cmp(&b.name));
    out
}

/// What the tracer has learnt so far.
#[derive(Default)]
struct State {
    structs: BTreeMap<String, Vec<String>>,
    enums: BTreeMap<String, Vec<String>>,
    /// Index of the variant each enum takes in the current pass.
    explored: BTreeMap<String, usize>,
    /// Enums met in this pass (an enum nested in itself takes its first variant).
    seen_this_pass: Vec<String>,
}

fn names(list: &'static [&'static str]) -> Vec<String> {
    list.iter().map(|s| s.to_string()).collect()
}

/// A deserializer that records types and answers with placeholders.
struct Tracer<'a> {
    state: &'a mut State,
}

impl<'de> de::Deserializer<'de> for Tracer<'_> {
    type Error = Error;

    fn deserialize_any<V: Visitor<'de>>(self, _v: V) -> Result<V::Value, Error> {
        Err(de::Error::custom("the scene tracer needs typed fields"))
    }
    fn deserialize_bool<V: Visitor<'de>>(self, v: V) -> Result<V::Value, Error> {
        v.visit_bool(false)
    }
    fn deserialize_f64<V: Visitor<'de>>(self, v: V) -> Result<V::Value, Error> {
        v.visit_f64(1.0)
    }
    fn deserialize_u64<V: Visitor<'de>>(self, v: V) -> Result<V::Value, Error> {
        v.visit_u64(1)
    }
    fn deserialize_u32<V: Visitor<'de>>(self, v: V) -> Result<V::Value, Error> {
        v.visit_u64(1)
    }
    fn deserialize_u16<V: Visitor<'de>>(self, v: V) -> Result<V::Value, Error> {
        v.visit_u64(1)
    }
    fn deserialize_u8<V: Visitor<'de>>(self, v: V) -> Result<V::Value, Error> {
        v.visit_u64(1)
    }
    fn deserialize_string<V: Visitor<'de>>(self, v: V) -> Result<V::Value, Error> {
        v.visit_string("x".into())
    }
    fn deserialize_str<V: Visitor<'de>>(self, v: V) -> Result<V::Value, Error> {
        v.visit_str("x")
    }
    fn deserialize_option<V: Visitor<'de>>(self, v: V) -> Result<V::Value, Error> {
        v.visit_some(self)
    }
    fn deserialize_seq<V: Visitor<'de>>(self, v: V) -> Result<V::Value, Error> {
        v.visit_seq(Seq {
            state: self.state,
            left: 1,
        })
    }
    fn deserialize_tuple<V: Visitor<'de>>(self, len: usize, v: V) -> Result<V::Value, Error> {
        v.visit_seq(Seq {
            state: self.state,
            left: len,
        })
    }
    fn deserialize_map<V: Visitor<'de>>(self, v: V) -> Result<V::Value, Error> {
        v.visit_map(Map {
            state: self.state,
            keys: vec!["x"],
        })
    }
    fn deserialize_struct<V: Visitor<'de>>(
        self,
        name: &'static str,
        fields: &'static [&'static str],
        v: V,
    ) -> Result<V::Value, Error> {
        self.state.structs.insert(name.into(), names(fields));
        v.visit_map(Map {
            state: self.state,
            keys: fields.to_vec(),
        })
    }
    fn deserialize_enum<V: Visitor<'de>>(
        self,
        name: &'static str,
        variants: &'static [&'static str],
        v: V,
    ) -> Result<V::Value, Error> {
        let st = self.state;
        st.enums.insert(name.into(), names(variants));
        let pick = if st.seen_this_pass.iter().any(|n| n == name) {
            0
        } else {
            st.seen_this_pass.push(name.into());
            st.explored.get(name).copied().unwrap_or(0)
        };
        v.visit_enum(Enum {
            state: st,
            enum_name: name,
            variant: variants[pick.min(variants.len() - 1)],
        })
    }

    serde::forward_to_deserialize_any! {
        i8 i16 i32 i64 i128 u128 f32 char bytes byte_buf unit unit_struct
        newtype_struct tuple_struct identifier ignored_any
    }
}

/// One element per sequence (enough to walk its element type), `len` per tuple.
struct Seq<'a> {
    state: &'a mut State,
    left: usize,
}

impl<'de> de::SeqAccess<'de> for Seq<'_> {
    type Error = Error;
    fn next_element_seed<T: DeserializeSeed<'de>>(
        &mut self,
        seed: T,
    ) -> Result<Option<T::Value>, Error> {
        if self.left == 0 {
            return Ok(None);
        }
        self.left -= 1;
        seed.deserialize(Tracer { state: self.state }).map(Some)
    }
}

/// Every field of a struct (or one entry of a map), each with a traced value.
struct Map<'a> {
    state: &'a mut State,
    keys: Vec<&'static str>,
}

impl<'de> de::MapAccess<'de> for Map<'_> {
    type Error = Error;
    fn next_key_seed<K: DeserializeSeed<'de>>(
        &mut self,
        seed: K,
    ) -> Result<Option<K::Value>, Error> {
        if self.keys.is_empty() {
            return Ok(None);
        }
        let key: StrDeserializer<'_, Error> = self.keys.remove(0).into_deserializer();
        seed.deserialize(key).map(Some)
    }
    fn next_value_seed<T: DeserializeSeed<'de>>(&mut self, seed: T) -> Result<T::Value, Error> {
        seed.deserialize(Tracer { state: self.state })
    }
}

/// The chosen variant of an enum.
struct Enum<'a> {
    state: &'a mut State,
    enum_name: &'static str,
    variant: &'static str,
}

impl<'de, 'a> de::EnumAccess<'de> for Enum<'a> {
    type Error = Error;
    type Variant = Enum<'a>;
    fn variant_seed<V: DeserializeSeed<'de>>(self, seed: V) -> Result<(V::Value, Self), Error> {
        let key: StrDeserializer<'_, Error> = self.variant.into_deserializer();
        Ok((seed.deserialize(key)?, self))
    }
}

impl<'de> de::VariantAccess<'de> for Enum<'_> {
    type Error = Error;
    fn unit_variant(self) -> Result<(), Error> {
        Ok(())
    }
    fn newtype_variant_seed<T: DeserializeSeed<'de>>(self, seed: T) -> Result<T::Value, Error> {
        seed.deserialize(Tracer { state: self.state })
    }
    fn tuple_variant<V: Visitor<'de>>(self, len: usize, v: V) -> Result<V::Value, Error> {
        v.visit_seq(Seq {
            state: self.state,
            left: len,
        })
    }
    fn struct_variant<V: Visitor<'de>>(
        self,
        fields: &'static [&'static str],
        v: V,
    ) -> Result<V::Value, Error> {
        let name = format!("{}::{}", self.enum_name, self.variant);
        self.state.structs.insert(name, names(fields));
        v.visit_map(Map {
            state: self.state,
            keys: fields.to_vec(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_tracer_walks_the_whole_scene() {
        let mut state = State::default();
        Scene::deserialize(Tracer { state: &mut state }).expect("placeholders are accepted");
        let schema = scene_schema();
        let get = |n: &str| schema.iter().find(|t| t.name == n).expect(n).clone();
        assert!(get("Scene").members.contains(&"growth".to_string()));
        assert!(get("Material").members.contains(&"E".to_string()));
        assert_eq!(
            get("Outline").members,
            ["Rectangle", "Polygon", "Edges", "Infinite"]
        );
        // Every variant walked: the fields of the last struct variants are known.
        assert!(get("Outline::Infinite")
            .members
            .contains(&"sxy".to_string()));
        assert!(get("Failure::Degradation")
            .members
            .contains(&"beta".to_string()));
        assert!(get("SwitchingParams")
            .members
            .contains(&"max_adr".to_string()));
        assert!(!get("Scene").members.contains(&"source".to_string()));
    }
}
