//! What a client is told when a request fails, and what only the server's log is told.
//!
//! The server is meant to be opened to a network (a human study), so an answer must never
//! carry the text of a file on the server: a message is built from the request itself and
//! from what the operator chose to offer, nothing else. A failure whose cause is on the
//! server's side (a record that cannot be read, a policy that misbehaves, a full disk) is
//! [`ApiError::Internal`]: its whole chain goes to the log under a number, and the client
//! gets only that number.

use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use axum::Json;
use serde_json::json;
use std::sync::atomic::{AtomicU64, Ordering};

/// A refused or failed request. Every variant but `Internal` holds a message that is safe
/// to send: it names the request's fault and what the server allows instead.
#[derive(Debug)]
pub enum ApiError {
    /// 400: the request is malformed or not allowed by the rules.
    BadRequest(String),
    /// 403: the session is not one this server issued.
    Forbidden(String),
    /// 404: no such game in this session.
    NotFound(String),
    /// 413: the body is larger than `--max-body`.
    TooLarge(String),
    /// 429: a limit of the session or of the server (games open, games per minute).
    TooMany(String),
    /// 500: the server's own fault; the cause is logged, never sent.
    Internal(anyhow::Error),
}

pub type ApiResult<T> = Result<T, ApiError>;

/// Numbers the internal errors, so that a participant's report ("error #12") finds the
/// log line.
static INCIDENTS: AtomicU64 = AtomicU64::new(1);

/// A client's string quoted in a message: at most 40 characters, control characters
/// escaped, so an answer can never carry more than a fragment of what was sent.
pub fn quoted(text: &str) -> String {
    let short: String = text.chars().take(40).collect();
    let more = if text.chars().count() > 40 { "…" } else { "" };
    format!("{:?}{more}", short)
}

impl From<anyhow::Error> for ApiError {
    /// Anything not classified as the client's fault is the server's: logged, not sent.
    fn from(e: anyhow::Error) -> ApiError {
        ApiError::Internal(e)
    }
}

impl ApiError {
    pub fn status(&self) -> StatusCode {
        match self {
            ApiError::BadRequest(_) => StatusCode::BAD_REQUEST,
            ApiError::Forbidden(_) => StatusCode::FORBIDDEN,
            ApiError::NotFound(_) => StatusCode::NOT_FOUND,
            ApiError::TooLarge(_) => StatusCode::PAYLOAD_TOO_LARGE,
            ApiError::TooMany(_) => StatusCode::TOO_MANY_REQUESTS,
            ApiError::Internal(_) => StatusCode::INTERNAL_SERVER_ERROR,
        }
    }
}

impl std::fmt::Display for ApiError {
    /// The message (for the operator's terminal at start; the page gets it as JSON).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ApiError::BadRequest(m)
            | ApiError::Forbidden(m)
            | ApiError::NotFound(m)
            | ApiError::TooLarge(m)
            | ApiError::TooMany(m) => f.write_str(m),
            ApiError::Internal(e) => write!(f, "{e:#}"),
        }
    }
}

impl IntoResponse for ApiError {
    fn into_response(self) -> Response {
        let status = self.status();
        let message = match self {
            ApiError::Internal(e) => {
                let n = INCIDENTS.fetch_add(1, Ordering::Relaxed);
                eprintln!("yokai serve: error #{n}: {e:#}");
                format!("the server could not serve this request (error #{n} in its log)")
            }
            refused => {
                let m = refused.to_string();
                eprintln!("yokai serve: refused ({}): {m}", status.as_u16());
                m
            }
        };
        (status, Json(json!({ "error": message }))).into_response()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_quoted_string_is_cut_to_forty_characters_and_escaped() {
        assert_eq!(quoted("belief"), "\"belief\"");
        let long = "x".repeat(100);
        assert_eq!(quoted(&long), format!("\"{}\"…", "x".repeat(40)));
        assert_eq!(quoted("a\nb"), "\"a\\nb\"");
    }

    #[test]
    fn an_internal_error_reaches_the_client_as_a_number_only() {
        let e = ApiError::from(anyhow::anyhow!("secret = 1234 in /srv/keys.toml"));
        let response = e.into_response();
        assert_eq!(response.status(), StatusCode::INTERNAL_SERVER_ERROR);
        let body = futures_body(response);
        assert!(!body.contains("secret") && !body.contains("keys"), "{body}");
        assert!(body.contains("error #"), "{body}");
    }

    fn futures_body(response: Response) -> String {
        let runtime = tokio::runtime::Builder::new_current_thread()
            .build()
            .unwrap();
        let bytes = runtime
            .block_on(axum::body::to_bytes(response.into_body(), 1 << 16))
            .unwrap();
        String::from_utf8(bytes.to_vec()).unwrap()
    }
}
