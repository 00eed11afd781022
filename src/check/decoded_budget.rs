//! A bound on the memory a message from a student's process decodes to.
//!
//! A frame's bytes are bounded ([`super::protocol::MAX_FRAME`]), but what
//! they decode to is not: an empty `String` is one byte on the wire and 24
//! in memory, a `None` one byte and the size of its `Option`. A frame of
//! 64 MiB of empty names decoded to 1.5 GB in the grader, once per chapter
//! checked at once. This wraps the decoder and charges every element of a
//! collection (a sequence or a map, not a struct's or a tuple's fields,
//! which live inside it) its size in memory before it is decoded; past the
//! budget the message is refused. (Text and bytes take on the heap what
//! they took on the wire, which the frame already bounds.)
//!
//! serde's `Deserializer` has no hook for this, so every part of it is
//! wrapped: the deserializer, the visitor it calls, and the accessors and
//! seeds the visitor is handed. Each forwards to the wrapped one.

use std::cell::Cell;

use serde::de::{self, DeserializeSeed, Deserializer, Visitor};

/// What is left to spend, in bytes, and whether a charge went past it.
pub struct Budget {
    left: Cell<usize>,
    spent: Cell<bool>,
}

impl Budget {
    pub fn new(bytes: usize) -> Budget {
        Budget {
            left: Cell::new(bytes),
            spent: Cell::new(false),
        }
    }

    /// Whether decoding stopped for want of budget (a decoder's own error
    /// may not carry the message it was given).
    pub fn spent(&self) -> bool {
        self.spent.get()
    }

    fn charge<E: de::Error>(&self, bytes: usize) -> Result<(), E> {
        match self.left.get().checked_sub(bytes) {
            Some(left) => {
                self.left.set(left);
                Ok(())
            }
            None => {
                self.spent.set(true);
                Err(E::custom("more memory than the budget"))
            }
        }
    }
}

/// `inner`, every element of a collection it decodes charged to
/// `budget`.
pub struct Charged<'b, D> {
    inner: D,
    budget: &'b Budget,
    /// Whether `inner` is a collection's visitor, accessor or element.
    collection: bool,
}

impl<'b, D> Charged<'b, D> {
    /// `inner` decoded within `budget`.
    pub fn new(inner: D, budget: &'b Budget) -> Charged<'b, D> {
        Charged {
            inner,
            budget,
            collection: false,
        }
    }

    fn wrap<T>(&self, inner: T) -> Charged<'b, T> {
        Charged::new(inner, self.budget)
    }

    /// `inner` as part of this, a collection when this is one.
    fn within<T>(&self, inner: T) -> Charged<'b, T> {
        Charged {
            collection: self.collection,
            ..self.wrap(inner)
        }
    }
}

macro_rules! forward_deserialize {
    ($collection:literal: $($method:ident($($argument:ident: $type:ty),*);)*) => {
        $(fn $method<V: Visitor<'de>>(self, $($argument: $type,)* visitor: V) -> Result<V::Value, Self::Error> {
            let visitor = Charged { collection: $collection, ..self.wrap(visitor) };
            self.inner.$method($($argument,)* visitor)
        })*
    };
}

impl<'de, D: Deserializer<'de>> Deserializer<'de> for Charged<'_, D> {
    type Error = D::Error;

    forward_deserialize! {
        true: deserialize_seq(); deserialize_map(); deserialize_any();
    }
    forward_deserialize! {
        false: deserialize_bool(); deserialize_i8(); deserialize_i16();
        deserialize_i32(); deserialize_i64(); deserialize_i128(); deserialize_u8();
        deserialize_u16(); deserialize_u32(); deserialize_u64(); deserialize_u128();
        deserialize_f32(); deserialize_f64(); deserialize_char(); deserialize_str();
        deserialize_string(); deserialize_bytes(); deserialize_byte_buf();
        deserialize_option(); deserialize_unit(); deserialize_identifier(); deserialize_ignored_any();
        deserialize_unit_struct(name: &'static str);
        deserialize_newtype_struct(name: &'static str);
        deserialize_tuple(length: usize);
        deserialize_tuple_struct(name: &'static str, length: usize);
        deserialize_struct(name: &'static str, fields: &'static [&'static str]);
        deserialize_enum(name: &'static str, variants: &'static [&'static str]);
    }

    fn is_human_readable(&self) -> bool {
        self.inner.is_human_readable()
    }
}

macro_rules! forward_visit {
    ($($method:ident($type:ty);)*) => {
        $(fn $method<E: de::Error>(self, value: $type) -> Result<Self::Value, E> {
            self.inner.$method(value)
        })*
    };
}

impl<'de, V: Visitor<'de>> Visitor<'de> for Charged<'_, V> {
    type Value = V::Value;

    fn expecting(&self, formatter: &mut std::fmt::Formatter) -> std::fmt::Result {
        self.inner.expecting(formatter)
    }

    forward_visit! {
        visit_bool(bool); visit_i8(i8); visit_i16(i16); visit_i32(i32); visit_i64(i64);
        visit_i128(i128); visit_u8(u8); visit_u16(u16); visit_u32(u32); visit_u64(u64);
        visit_u128(u128); visit_f32(f32); visit_f64(f64); visit_char(char);
        visit_str(&str); visit_borrowed_str(&'de str); visit_string(String);
        visit_bytes(&[u8]); visit_borrowed_bytes(&'de [u8]); visit_byte_buf(Vec<u8>);
    }

    fn visit_none<E: de::Error>(self) -> Result<Self::Value, E> {
        self.inner.visit_none()
    }

    fn visit_unit<E: de::Error>(self) -> Result<Self::Value, E> {
        self.inner.visit_unit()
    }

    fn visit_some<D: Deserializer<'de>>(self, inner: D) -> Result<Self::Value, D::Error> {
        let inner = self.wrap(inner);
        self.inner.visit_some(inner)
    }

    fn visit_newtype_struct<D: Deserializer<'de>>(self, inner: D) -> Result<Self::Value, D::Error> {
        let inner = self.wrap(inner);
        self.inner.visit_newtype_struct(inner)
    }

    fn visit_seq<A: de::SeqAccess<'de>>(self, access: A) -> Result<Self::Value, A::Error> {
        let access = self.within(access);
        self.inner.visit_seq(access)
    }

    fn visit_map<A: de::MapAccess<'de>>(self, access: A) -> Result<Self::Value, A::Error> {
        let access = self.within(access);
        self.inner.visit_map(access)
    }

    fn visit_enum<A: de::EnumAccess<'de>>(self, access: A) -> Result<Self::Value, A::Error> {
        let access = self.wrap(access);
        self.inner.visit_enum(access)
    }
}

/// A seed, charged its value's size before it is decoded when it is a
/// collection's element.
impl<'de, T: DeserializeSeed<'de>> DeserializeSeed<'de> for Charged<'_, T> {
    type Value = T::Value;

    fn deserialize<D: Deserializer<'de>>(self, inner: D) -> Result<Self::Value, D::Error> {
        if self.collection {
            // At least a byte: a sequence of zero-sized values is still work.
            self.budget.charge(std::mem::size_of::<T::Value>().max(1))?;
        }
        let inner = self.wrap(inner);
        self.inner.deserialize(inner)
    }
}

impl<'de, A: de::SeqAccess<'de>> de::SeqAccess<'de> for Charged<'_, A> {
    type Error = A::Error;

    fn next_element_seed<T: DeserializeSeed<'de>>(
        &mut self,
        seed: T,
    ) -> Result<Option<T::Value>, Self::Error> {
        let seed = self.within(seed);
        self.inner.next_element_seed(seed)
    }

    fn size_hint(&self) -> Option<usize> {
        self.inner.size_hint()
    }
}

impl<'de, A: de::MapAccess<'de>> de::MapAccess<'de> for Charged<'_, A> {
    type Error = A::Error;

    fn next_key_seed<K: DeserializeSeed<'de>>(
        &mut self,
        seed: K,
    ) -> Result<Option<K::Value>, Self::Error> {
        let seed = self.within(seed);
        self.inner.next_key_seed(seed)
    }

    fn next_value_seed<V: DeserializeSeed<'de>>(
        &mut self,
        seed: V,
    ) -> Result<V::Value, Self::Error> {
        let seed = self.within(seed);
        self.inner.next_value_seed(seed)
    }

    fn size_hint(&self) -> Option<usize> {
        self.inner.size_hint()
    }
}

impl<'b, 'de, A: de::EnumAccess<'de>> de::EnumAccess<'de> for Charged<'b, A> {
    type Error = A::Error;
    type Variant = Charged<'b, A::Variant>;

    fn variant_seed<V: DeserializeSeed<'de>>(
        self,
        seed: V,
    ) -> Result<(V::Value, Self::Variant), Self::Error> {
        let budget = self.budget;
        // The variant's name or index: no element of its own.
        let (value, variant) = self.inner.variant_seed(seed)?;
        Ok((value, Charged::new(variant, budget)))
    }
}

impl<'de, A: de::VariantAccess<'de>> de::VariantAccess<'de> for Charged<'_, A> {
    type Error = A::Error;

    fn unit_variant(self) -> Result<(), Self::Error> {
        self.inner.unit_variant()
    }

    fn newtype_variant_seed<T: DeserializeSeed<'de>>(
        self,
        seed: T,
    ) -> Result<T::Value, Self::Error> {
        // Not charged: the variant's value is inside its enum, as a field
        // is inside its struct.
        let seed = self.wrap(seed);
        self.inner.newtype_variant_seed(seed)
    }

    fn tuple_variant<V: Visitor<'de>>(
        self,
        length: usize,
        visitor: V,
    ) -> Result<V::Value, Self::Error> {
        let visitor = self.wrap(visitor);
        self.inner.tuple_variant(length, visitor)
    }

    fn struct_variant<V: Visitor<'de>>(
        self,
        fields: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, Self::Error> {
        let visitor = self.wrap(visitor);
        self.inner.struct_variant(fields, visitor)
    }
}
