//! Who is asking, and whether they may write.
//!
//! The user is the `x-frep-user` header (trimmed, 1–64 printable
//! characters), else [`DEFAULT_USER`]: the local studio has no accounts.
//! This is identification, not authentication. A deployment that needs real
//! users puts an authenticating proxy in front that sets the header.
//!
//! Writes to an existing model are allowed when the configuration is
//! `open_access`. Otherwise they are allowed only when the store says the
//! user may edit it (the owner). Refused writes get 403.

use std::convert::Infallible;

use axum::extract::FromRequestParts;
use axum::http::request::Parts;

use crate::error::AppError;
use crate::state::AppState;

/// The header naming the user.
pub const USER_HEADER: &str = "x-frep-user";

/// The user when the header is absent.
pub const DEFAULT_USER: &str = "studio";

/// Longest user name accepted from the header.
const MAX_USER_CHARS: usize = 64;

/// The requesting user.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct User(pub String);

impl User {
    /// The user of a request's headers: the header when it is a sensible
    /// name, else the default. A malformed header is not an error. It only
    /// identifies, and the default has no more rights than any name.
    pub fn from_headers(headers: &axum::http::HeaderMap) -> User {
        let name = headers
            .get(USER_HEADER)
            .and_then(|v| v.to_str().ok())
            .map(str::trim)
            .filter(|s| {
                !s.is_empty()
                    && s.chars().count() <= MAX_USER_CHARS
                    && s.chars().all(|c| !c.is_control())
            });
        User(name.unwrap_or(DEFAULT_USER).to_string())
    }

    /// Refuses with 403 unless the user may edit `model_id`.
    pub async fn check_edit(&self, state: &AppState, model_id: &str) -> Result<(), AppError> {
        if state.config.open_access {
            return Ok(());
        }
        let (user, id) = (self.0.clone(), model_id.to_string());
        let allowed = state
            .store_call(move |store| store.may_edit(&id, &user))
            .await?;
        if allowed {
            Ok(())
        } else {
            Err(AppError::Forbidden(format!(
                "user {} may not edit model {model_id}",
                self.0
            )))
        }
    }
}

impl<S: Send + Sync> FromRequestParts<S> for User {
    type Rejection = Infallible;

    async fn from_request_parts(parts: &mut Parts, _: &S) -> Result<User, Infallible> {
        Ok(User::from_headers(&parts.headers))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use axum::http::{HeaderMap, HeaderValue};

    #[test]
    fn header_or_default() {
        let mut h = HeaderMap::new();
        assert_eq!(User::from_headers(&h).0, DEFAULT_USER);
        h.insert(USER_HEADER, HeaderValue::from_static("  ada "));
        assert_eq!(User::from_headers(&h).0, "ada");
        h.insert(USER_HEADER, HeaderValue::from_static(""));
        assert_eq!(User::from_headers(&h).0, DEFAULT_USER);
        let long = "x".repeat(MAX_USER_CHARS + 1);
        h.insert(USER_HEADER, HeaderValue::from_str(&long).unwrap());
        assert_eq!(User::from_headers(&h).0, DEFAULT_USER);
    }
}
