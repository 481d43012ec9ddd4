//! The serializing half of [`super`]: externally tagged calls turned into the calls of
//! serde's internal tagging, `kind` first.

use std::fmt::Display;

use serde::ser::{self, Impossible, Serialize, SerializeMap, SerializeStruct, Serializer};

use super::TAG;

/// Serializes an externally tagged enum as a table with `kind` first, as serde's internal
/// tagging does: unit, newtype (of a struct or map) and struct variants.
pub struct TagSerializer<S> {
    inner: S,
}

impl<S> TagSerializer<S> {
    pub fn new(inner: S) -> Self {
        TagSerializer { inner }
    }
}

fn not_tagged<E: ser::Error>(what: impl Display) -> E {
    E::custom(format!(
        "cannot serialize {what} as a `kind`-tagged table (unit, newtype or struct variants only)"
    ))
}

/// The `Serializer` methods that reject their input with `not_tagged`.
macro_rules! reject {
    ($($method:ident($ty:ty)),* $(,)?) => {
        $(
            fn $method(self, _value: $ty) -> Result<Self::Ok, Self::Error> {
                Err(not_tagged(stringify!($ty)))
            }
        )*
    };
}

/// The `Serializer` methods other than those that carry a tagged variant.
macro_rules! reject_all_but_variants {
    () => {
        reject! {
            serialize_bool(bool), serialize_i8(i8), serialize_i16(i16), serialize_i32(i32),
            serialize_i64(i64), serialize_u8(u8), serialize_u16(u16), serialize_u32(u32),
            serialize_u64(u64), serialize_f32(f32), serialize_f64(f64), serialize_char(char),
            serialize_str(&str), serialize_bytes(&[u8]),
        }

        fn serialize_none(self) -> Result<Self::Ok, Self::Error> {
            Err(not_tagged("none"))
        }

        fn serialize_some<T: ?Sized + Serialize>(
            self,
            _value: &T,
        ) -> Result<Self::Ok, Self::Error> {
            Err(not_tagged("an option"))
        }

        fn serialize_unit(self) -> Result<Self::Ok, Self::Error> {
            Err(not_tagged("a unit"))
        }

        fn serialize_unit_struct(self, name: &'static str) -> Result<Self::Ok, Self::Error> {
            Err(not_tagged(name))
        }

        fn serialize_newtype_struct<T: ?Sized + Serialize>(
            self,
            name: &'static str,
            _value: &T,
        ) -> Result<Self::Ok, Self::Error> {
            Err(not_tagged(name))
        }

        fn serialize_seq(self, _len: Option<usize>) -> Result<Self::SerializeSeq, Self::Error> {
            Err(not_tagged("a sequence"))
        }

        fn serialize_tuple(self, _len: usize) -> Result<Self::SerializeTuple, Self::Error> {
            Err(not_tagged("a tuple"))
        }

        fn serialize_tuple_struct(
            self,
            name: &'static str,
            _len: usize,
        ) -> Result<Self::SerializeTupleStruct, Self::Error> {
            Err(not_tagged(name))
        }

        fn serialize_tuple_variant(
            self,
            name: &'static str,
            _index: u32,
            variant: &'static str,
            _len: usize,
        ) -> Result<Self::SerializeTupleVariant, Self::Error> {
            Err(not_tagged(format_args!("{name}::{variant}")))
        }
    };
}

impl<S: Serializer> Serializer for TagSerializer<S> {
    type Ok = S::Ok;
    type Error = S::Error;
    type SerializeSeq = Impossible<S::Ok, S::Error>;
    type SerializeTuple = Impossible<S::Ok, S::Error>;
    type SerializeTupleStruct = Impossible<S::Ok, S::Error>;
    type SerializeTupleVariant = Impossible<S::Ok, S::Error>;
    type SerializeMap = Impossible<S::Ok, S::Error>;
    type SerializeStruct = Impossible<S::Ok, S::Error>;
    type SerializeStructVariant = StructVariant<S::SerializeStruct>;

    reject_all_but_variants!();

    fn serialize_unit_variant(
        self,
        name: &'static str,
        _index: u32,
        variant: &'static str,
    ) -> ::core::result::Result<S::Ok, S::Error> {
        let mut table = self.inner.serialize_struct(name, 1)?;
        table.serialize_field(TAG, variant)?;
        table.end()
    }

    fn serialize_newtype_variant<T: ?Sized + Serialize>(
        self,
        _name: &'static str,
        _index: u32,
        variant: &'static str,
        value: &T,
    ) -> ::core::result::Result<S::Ok, S::Error> {
        value.serialize(TagFirst {
            inner: self.inner,
            variant,
        })
    }

    fn serialize_map(self, _len: Option<usize>) -> Result<Self::SerializeMap, S::Error> {
        Err(not_tagged("a map"))
    }

    fn serialize_struct(
        self,
        name: &'static str,
        _len: usize,
    ) -> Result<Self::SerializeStruct, S::Error> {
        Err(not_tagged(name))
    }

    fn serialize_struct_variant(
        self,
        name: &'static str,
        _index: u32,
        variant: &'static str,
        len: usize,
    ) -> Result<Self::SerializeStructVariant, S::Error> {
        let mut table = self.inner.serialize_struct(name, len + 1)?;
        table.serialize_field(TAG, variant)?;
        Ok(StructVariant(table))
    }
}

/// The fields of a struct variant, after its `kind`.
pub struct StructVariant<T>(T);

impl<T: SerializeStruct> ser::SerializeStructVariant for StructVariant<T> {
    type Ok = T::Ok;
    type Error = T::Error;

    fn serialize_field<V: ?Sized + Serialize>(
        &mut self,
        key: &'static str,
        value: &V,
    ) -> Result<(), T::Error> {
        self.0.serialize_field(key, value)
    }

    fn skip_field(&mut self, key: &'static str) -> Result<(), T::Error> {
        self.0.skip_field(key)
    }

    fn end(self) -> Result<T::Ok, T::Error> {
        self.0.end()
    }
}

/// The content of a newtype variant, a struct or map, with `kind = variant` first.
struct TagFirst<S> {
    inner: S,
    variant: &'static str,
}

impl<S: Serializer> Serializer for TagFirst<S> {
    type Ok = S::Ok;
    type Error = S::Error;
    type SerializeSeq = Impossible<S::Ok, S::Error>;
    type SerializeTuple = Impossible<S::Ok, S::Error>;
    type SerializeTupleStruct = Impossible<S::Ok, S::Error>;
    type SerializeTupleVariant = Impossible<S::Ok, S::Error>;
    type SerializeMap = S::SerializeMap;
    type SerializeStruct = S::SerializeStruct;
    type SerializeStructVariant = Impossible<S::Ok, S::Error>;

    reject_all_but_variants!();

    fn serialize_unit_variant(
        self,
        name: &'static str,
        _index: u32,
        variant: &'static str,
    ) -> ::core::result::Result<S::Ok, S::Error> {
        Err(not_tagged(format_args!("{name}::{variant}")))
    }

    fn serialize_newtype_variant<T: ?Sized + Serialize>(
        self,
        name: &'static str,
        _index: u32,
        variant: &'static str,
        _value: &T,
    ) -> ::core::result::Result<S::Ok, S::Error> {
        Err(not_tagged(format_args!("{name}::{variant}")))
    }

    fn serialize_map(self, len: Option<usize>) -> Result<S::SerializeMap, S::Error> {
        let mut map = self.inner.serialize_map(len.map(|n| n + 1))?;
        map.serialize_entry(TAG, self.variant)?;
        Ok(map)
    }

    fn serialize_struct(
        self,
        name: &'static str,
        len: usize,
    ) -> Result<S::SerializeStruct, S::Error> {
        let mut table = self.inner.serialize_struct(name, len + 1)?;
        table.serialize_field(TAG, self.variant)?;
        Ok(table)
    }

    fn serialize_struct_variant(
        self,
        name: &'static str,
        _index: u32,
        variant: &'static str,
        _len: usize,
    ) -> Result<Self::SerializeStructVariant, S::Error> {
        Err(not_tagged(format_args!("{name}::{variant}")))
    }
}
