//! Enums tagged by a `kind` key (`{ kind = "half_car", preset = "two_axle_truck" }`)
//! whose deserialization errors keep the path inside the variant.
//!
//! Serde's derived internally tagged enums buffer the whole table, read the tag, and then
//! deserialize the variant from the buffer, where a path tracker (`serde_path_to_error`)
//! cannot follow: an unknown key `wings` in `vehicles.0.model` is reported at
//! `vehicles.0.model` (dtolnay/path-to-error#1). An enum here derives its externally
//! tagged form as inherent functions (`#[serde(remote = "Self")]`) and gets `Serialize`
//! and `Deserialize` from [`kind_tagged!`]:
//!
//! - deserializing buffers the table, takes `kind`, and deserializes the variant from the
//!   rest under its own path tracker; an error there carries the path below the enum in
//!   its message (`at `wings`: unknown field ...`), which [`split_path`] takes apart;
//! - serializing turns the externally tagged calls back into a table with `kind` first,
//!   the same calls serde's internal tagging makes, so the TOML written is unchanged.

use std::collections::BTreeMap;

use serde::de::{
    self, Deserialize, DeserializeSeed, Deserializer, EnumAccess, IntoDeserializer, VariantAccess,
};
use serde_value::{Value, ValueDeserializer};

mod ser;

pub use ser::{StructVariant, TagSerializer};

/// The key that names the variant.
pub const TAG: &str = "kind";

/// Implements `Serialize` and `Deserialize` for an enum tagged by `kind`, from the
/// inherent externally tagged functions that `#[derive(Serialize, Deserialize)]` with
/// `#[serde(remote = "Self")]` generates.
macro_rules! kind_tagged {
    ($ty:ty) => {
        impl ::serde::Serialize for $ty {
            fn serialize<S: ::serde::Serializer>(
                &self,
                serializer: S,
            ) -> ::core::result::Result<S::Ok, S::Error> {
                <$ty>::serialize(self, $crate::base::tagged::TagSerializer::new(serializer))
            }
        }

        impl<'de> ::serde::Deserialize<'de> for $ty {
            fn deserialize<D: ::serde::Deserializer<'de>>(
                deserializer: D,
            ) -> ::core::result::Result<Self, D::Error> {
                $crate::base::tagged::deserialize(deserializer, <$ty>::deserialize)
            }
        }
    };
}
pub(crate) use kind_tagged;

/// Deserializes a `kind`-tagged table through `external`, the enum's externally tagged
/// deserializer.
pub fn deserialize<'de, D, T>(
    deserializer: D,
    external: impl FnOnce(Tagged<D::Error>) -> Result<T, D::Error>,
) -> Result<T, D::Error>
where
    D: Deserializer<'de>,
{
    let mut table = match Value::deserialize(deserializer)? {
        Value::Map(table) => table,
        other => {
            return Err(de::Error::invalid_type(
                unexpected(&other),
                &"a table with a `kind` key",
            ))
        }
    };
    let kind = match table.remove(&Value::String(TAG.into())) {
        Some(Value::String(kind)) => kind,
        Some(other) => {
            let e: D::Error = de::Error::invalid_type(unexpected(&other), &"a variant name");
            return Err(de::Error::custom(with_path(TAG, e.to_string().trim_end())));
        }
        None => return Err(de::Error::missing_field(TAG)),
    };
    external(Tagged {
        kind,
        body: table,
        error: std::marker::PhantomData,
    })
}

/// What an error message looks like when its path is below a tagged enum.
const PATH_OPEN: &str = "at `";
const PATH_CLOSE: &str = "`: ";

/// The message of an error raised at `path` below a tagged enum.
fn with_path(path: &str, message: &str) -> String {
    format!("{PATH_OPEN}{path}{PATH_CLOSE}{message}")
}

/// Splits a message written by this module into the path below the tagged enum and the
/// message proper; other messages come back whole, with no path.
pub fn split_path(message: &str) -> (Option<&str>, &str) {
    message
        .strip_prefix(PATH_OPEN)
        .and_then(|rest| rest.split_once(PATH_CLOSE))
        .map_or((None, message), |(path, rest)| (Some(path), rest))
}

/// A path in the scenario's notation, `vehicles.0.model` (serde_path_to_error writes
/// `vehicles[0].model`, and `.` for the top); empty at the top.
pub fn dotted(path: &serde_path_to_error::Path) -> String {
    use serde_path_to_error::Segment;
    let segments: Vec<String> = path
        .iter()
        .map(|segment| match segment {
            Segment::Seq { index } => index.to_string(),
            Segment::Map { key } => key.clone(),
            Segment::Enum { variant } => variant.clone(),
            Segment::Unknown => "?".to_string(),
        })
        .collect();
    segments.join(".")
}

/// `outer.inner`, either part possibly empty.
pub fn join_path(outer: &str, inner: &str) -> String {
    match (outer.is_empty(), inner.is_empty()) {
        (_, true) => outer.to_string(),
        (true, false) => inner.to_string(),
        (false, false) => format!("{outer}.{inner}"),
    }
}

/// The variant body of a tagged table, deserialized under its own path tracker.
fn body_deserialize<E, T>(
    body: BTreeMap<Value, Value>,
    deserialize: impl FnOnce(
        serde_path_to_error::Deserializer<'_, '_, ValueDeserializer<E>>,
    ) -> Result<T, E>,
) -> Result<T, E>
where
    E: de::Error,
{
    let mut track = serde_path_to_error::Track::new();
    let tracked = serde_path_to_error::Deserializer::new(
        ValueDeserializer::new(Value::Map(body)),
        &mut track,
    );
    deserialize(tracked).map_err(|e| {
        let path = dotted(&track.path());
        // Trimmed: a format's Display may end its message with a newline (toml does).
        let message = e.to_string();
        let (inner, message) = split_path(message.trim_end());
        let path = join_path(&path, inner.unwrap_or(""));
        if path.is_empty() {
            E::custom(message)
        } else {
            E::custom(with_path(&path, message))
        }
    })
}

/// A tagged table as an externally tagged enum: the variant `kind` with `body`.
pub struct Tagged<E> {
    kind: String,
    body: BTreeMap<Value, Value>,
    error: std::marker::PhantomData<E>,
}

impl<'de, E: de::Error> Deserializer<'de> for Tagged<E> {
    type Error = E;

    fn deserialize_any<V: de::Visitor<'de>>(self, _visitor: V) -> Result<V::Value, E> {
        Err(E::custom(
            "a `kind`-tagged table deserializes only as an enum",
        ))
    }

    fn deserialize_enum<V: de::Visitor<'de>>(
        self,
        _name: &'static str,
        _variants: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, E> {
        visitor.visit_enum(self)
    }

    serde::forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes byte_buf
        option unit unit_struct newtype_struct seq tuple tuple_struct map struct identifier
        ignored_any
    }
}

impl<'de, E: de::Error> EnumAccess<'de> for Tagged<E> {
    type Error = E;
    type Variant = Body<E>;

    fn variant_seed<V: DeserializeSeed<'de>>(self, seed: V) -> Result<(V::Value, Body<E>), E> {
        let variant = seed
            .deserialize(self.kind.into_deserializer())
            .map_err(|e: E| E::custom(with_path(TAG, e.to_string().trim_end())))?;
        Ok((
            variant,
            Body {
                body: self.body,
                error: std::marker::PhantomData,
            },
        ))
    }
}

/// The keys of a tagged table other than `kind`.
pub struct Body<E> {
    body: BTreeMap<Value, Value>,
    error: std::marker::PhantomData<E>,
}

impl<'de, E: de::Error> VariantAccess<'de> for Body<E> {
    type Error = E;

    fn unit_variant(self) -> Result<(), E> {
        // A unit variant has no fields: any other key is unknown.
        match self.body.into_keys().next() {
            None => Ok(()),
            Some(Value::String(key)) => Err(E::custom(with_path(
                &key,
                &format!("unknown field `{key}`, there are no fields"),
            ))),
            Some(other) => Err(de::Error::invalid_type(unexpected(&other), &"a key")),
        }
    }

    fn newtype_variant_seed<T: DeserializeSeed<'de>>(self, seed: T) -> Result<T::Value, E> {
        body_deserialize(self.body, |de| seed.deserialize(de))
    }

    fn tuple_variant<V: de::Visitor<'de>>(self, _len: usize, _visitor: V) -> Result<V::Value, E> {
        Err(E::custom("a `kind`-tagged table has no tuple variants"))
    }

    fn struct_variant<V: de::Visitor<'de>>(
        self,
        fields: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, E> {
        body_deserialize(self.body, |de| de.deserialize_struct("", fields, visitor))
    }
}

/// The buffered value as `Unexpected`, for type errors.
fn unexpected(value: &Value) -> de::Unexpected<'_> {
    match value {
        Value::Bool(b) => de::Unexpected::Bool(*b),
        Value::I8(i) => de::Unexpected::Signed(i64::from(*i)),
        Value::I16(i) => de::Unexpected::Signed(i64::from(*i)),
        Value::I32(i) => de::Unexpected::Signed(i64::from(*i)),
        Value::I64(i) => de::Unexpected::Signed(*i),
        Value::U8(u) => de::Unexpected::Unsigned(u64::from(*u)),
        Value::U16(u) => de::Unexpected::Unsigned(u64::from(*u)),
        Value::U32(u) => de::Unexpected::Unsigned(u64::from(*u)),
        Value::U64(u) => de::Unexpected::Unsigned(*u),
        Value::F32(f) => de::Unexpected::Float(f64::from(*f)),
        Value::F64(f) => de::Unexpected::Float(*f),
        Value::Char(c) => de::Unexpected::Char(*c),
        Value::String(s) => de::Unexpected::Str(s),
        Value::Unit => de::Unexpected::Unit,
        Value::Option(_) => de::Unexpected::Option,
        Value::Newtype(_) => de::Unexpected::NewtypeStruct,
        Value::Seq(_) => de::Unexpected::Seq,
        Value::Map(_) => de::Unexpected::Map,
        Value::Bytes(b) => de::Unexpected::Bytes(b),
    }
}

#[cfg(test)]
mod tests;
