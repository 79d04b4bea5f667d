//! Column types both engines store the same way, decoded in one place.
//!
//! Yes/no columns are integers, 0 or 1: the `Any` driver reads an SQLite integer as a number,
//! never as a boolean, so one schema type keeps one decoding. Rows decode a flag through
//! [`Flag`] (`#[sqlx(try_from = "Flag")]`); statements bind `i64::from(flag)`. Documents (an
//! entry, a trial) are JSON text, parsed by [`JsonText`]. Ids (an EPC in hex, a robot id, a
//! UUID, a task's state) are text, parsed as they are read through [`Id`] and [`MaybeId`]
//! (`#[sqlx(try_from = "Id<Epc>")]`), so a row hands out the same types the API parsed.
//! Moments are text too, in [`crate::clock::format`]'s fixed width so they sort as text; rows
//! read them through [`At`] and [`MaybeAt`], and statements bind `At(moment)`.

use sqlx::any::AnyValueRef;
use sqlx::decode::Decode;
use sqlx::encode::{Encode, IsNull};
use sqlx::error::BoxDynError;
use sqlx::types::Type;
use sqlx::{Any, ValueRef};
use time::OffsetDateTime;

use crate::clock;

/// The column type a decoded type is stored as (`, for T` when the type is generic in `T`).
macro_rules! stored_as {
    ($decoded:ty, $stored:ty $(, for $param:ident)?) => {
        impl$(<$param>)? Type<Any> for $decoded {
            fn type_info() -> sqlx::any::AnyTypeInfo {
                <$stored as Type<Any>>::type_info()
            }

            fn compatible(ty: &sqlx::any::AnyTypeInfo) -> bool {
                <$stored as Type<Any>>::compatible(ty)
            }
        }
    };
}

/// A non-null flag column.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Flag(pub bool);

/// A flag column that may be null (a verdict not given yet).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MaybeFlag(pub Option<bool>);

stored_as!(Flag, i64);

impl<'r> Decode<'r, Any> for Flag {
    fn decode(value: AnyValueRef<'r>) -> Result<Self, BoxDynError> {
        Ok(Self(<i64 as Decode<Any>>::decode(value)? != 0))
    }
}

stored_as!(MaybeFlag, i64);

impl<'r> Decode<'r, Any> for MaybeFlag {
    fn decode(value: AnyValueRef<'r>) -> Result<Self, BoxDynError> {
        if value.is_null() {
            return Ok(Self(None));
        }
        Ok(Self(Some(<i64 as Decode<Any>>::decode(value)? != 0)))
    }
}

/// `From` a column type to the value it holds, which rows decode through `try_from`.
macro_rules! holds {
    ($($column:ty => $value:ty),* $(,)?) => {$(
        impl From<$column> for $value {
            fn from(column: $column) -> Self {
                column.0
            }
        }
    )*};
}

holds!(Flag => bool, MaybeFlag => Option<bool>);

/// A JSON document stored as text.
#[derive(Debug, Clone, PartialEq)]
pub struct JsonText(pub serde_json::Value);

stored_as!(JsonText, String);

impl<'r> Decode<'r, Any> for JsonText {
    fn decode(value: AnyValueRef<'r>) -> Result<Self, BoxDynError> {
        let text = <&str as Decode<Any>>::decode(value)?;
        Ok(Self(serde_json::from_str(text)?))
    }
}

holds!(JsonText => serde_json::Value);

/// A non-null id column, parsed as it is read.
#[derive(Debug, Clone, PartialEq)]
pub struct Id<T>(pub T);

/// An id column that may be null (a task for anyone, a trial not recorded yet).
#[derive(Debug, Clone, PartialEq)]
pub struct MaybeId<T>(pub Option<T>);

stored_as!(Id<T>, String, for T);
stored_as!(MaybeId<T>, String, for T);

impl<'r, T> Decode<'r, Any> for Id<T>
where
    T: std::str::FromStr,
    T::Err: std::error::Error + Send + Sync + 'static,
{
    fn decode(value: AnyValueRef<'r>) -> Result<Self, BoxDynError> {
        Ok(Self(<&str as Decode<Any>>::decode(value)?.parse()?))
    }
}

impl<'r, T> Decode<'r, Any> for MaybeId<T>
where
    T: std::str::FromStr,
    T::Err: std::error::Error + Send + Sync + 'static,
{
    fn decode(value: AnyValueRef<'r>) -> Result<Self, BoxDynError> {
        if value.is_null() {
            return Ok(Self(None));
        }
        Ok(Self(Some(<&str as Decode<Any>>::decode(value)?.parse()?)))
    }
}

/// `From` for each id type a row holds (one generic impl would break the orphan rule).
macro_rules! id_column {
    ($($id:ty),*) => {$(
        impl From<Id<$id>> for $id {
            fn from(column: Id<$id>) -> Self {
                column.0
            }
        }

        impl From<MaybeId<$id>> for Option<$id> {
            fn from(column: MaybeId<$id>) -> Self {
                column.0
            }
        }
    )*};
}

id_column!(pps_schema::Epc, pps_schema::RobotId, pps_schema::TaskState, uuid::Uuid);

/// A moment column, non-null, stored as [`clock::format`] writes it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct At(pub OffsetDateTime);

/// A moment column that may be null (a lease not given, a token that never expires).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MaybeAt(pub Option<OffsetDateTime>);

stored_as!(At, String);
stored_as!(MaybeAt, String);

/// A stored moment, or an error quoting the text that is not one.
fn parse_moment(text: &str) -> Result<OffsetDateTime, BoxDynError> {
    clock::parse(text).ok_or_else(|| format!("{text:?} is not an RFC 3339 timestamp").into())
}

impl<'r> Decode<'r, Any> for At {
    fn decode(value: AnyValueRef<'r>) -> Result<Self, BoxDynError> {
        Ok(Self(parse_moment(<&str as Decode<Any>>::decode(value)?)?))
    }
}

impl<'r> Decode<'r, Any> for MaybeAt {
    fn decode(value: AnyValueRef<'r>) -> Result<Self, BoxDynError> {
        if value.is_null() {
            return Ok(Self(None));
        }
        Ok(Self(Some(parse_moment(<&str as Decode<Any>>::decode(value)?)?)))
    }
}

impl Encode<'_, Any> for At {
    fn encode_by_ref(
        &self,
        buf: &mut <Any as sqlx::Database>::ArgumentBuffer,
    ) -> Result<IsNull, BoxDynError> {
        <String as Encode<Any>>::encode(clock::format(self.0), buf)
    }
}

impl Encode<'_, Any> for MaybeAt {
    fn encode_by_ref(
        &self,
        buf: &mut <Any as sqlx::Database>::ArgumentBuffer,
    ) -> Result<IsNull, BoxDynError> {
        <Option<String> as Encode<Any>>::encode(self.0.map(clock::format), buf)
    }
}

holds!(At => OffsetDateTime, MaybeAt => Option<OffsetDateTime>);
