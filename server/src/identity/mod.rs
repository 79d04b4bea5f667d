//! Who a caller is, below every layer that checks it: the roles of DESIGN §4, login names,
//! passwords and bearer secrets. The store keeps them and `auth` checks them over HTTP; neither
//! is needed to say what they are.

pub mod password;
mod role;
pub mod secret;
pub mod user_name;

pub use role::Role;
pub use user_name::UserName;
