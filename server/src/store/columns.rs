//! Column types both engines store the same way, decoded in one place.
//!
//! Yes/no columns are integers, 0 or 1: the `Any` driver reads an SQLite integer as a number,
//! never as a boolean, so one schema type keeps one decoding. Rows decode a flag through
//! [`Flag`] (`#[sqlx(try_from = "Flag")]`); statements bind `i64::from(flag)`. Documents (an
//! entry, a trial) are JSON text, parsed by [`JsonText`].

use sqlx::any::AnyValueRef;
use sqlx::decode::Decode;
use sqlx::error::BoxDynError;
use sqlx::types::Type;
use sqlx::{Any, ValueRef};

/// The column type a decoded type is stored as.
macro_rules! stored_as {
    ($decoded:ty, $stored:ty) => {
        impl Type<Any> for $decoded {
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

impl From<Flag> for bool {
    fn from(flag: Flag) -> Self {
        flag.0
    }
}

impl From<MaybeFlag> for Option<bool> {
    fn from(flag: MaybeFlag) -> Self {
        flag.0
    }
}

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

impl From<JsonText> for serde_json::Value {
    fn from(text: JsonText) -> Self {
        text.0
    }
}
