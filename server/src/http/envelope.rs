//! What every request and response passes through, whichever route takes it: the metrics
//! count, the anti-forgery check, axum's bare 405 turned into a problem document, and the
//! security headers.
//!
//! One hand-written layer rather than a middleware each: axum boxes every layer given to
//! `Router::layer` around each route and clones the whole boxed stack on every call, which
//! was a third of the robots' hot path. Here the future is a plain struct, not a boxed one.

use std::convert::Infallible;
use std::future::Future;
use std::pin::Pin;
use std::sync::Arc;
use std::task::{Context, Poll};
use std::time::Instant;

use axum::extract::{MatchedPath, Request};
use axum::http::header::{self, CONTENT_TYPE, HeaderName};
use axum::http::{HeaderMap, HeaderValue, Method, StatusCode, Uri};
use axum::response::{IntoResponse, Response};
use pin_project_lite::pin_project;
use tower::{Layer, Service};

use crate::http::{csrf, fallback};
use crate::ops::metrics::{Metrics, RouteMetrics};

/// Headers every response carries unless it set its own; the UI's Content-Security-Policy
/// forbids inline script. Values made once: `from_static` checks every byte each time it runs.
static SECURITY_HEADERS: [(HeaderName, HeaderValue); 4] = [
    (
        header::CONTENT_SECURITY_POLICY,
        HeaderValue::from_static(
            "default-src 'self'; script-src 'self'; style-src 'self'; img-src 'self' data:; \
             connect-src 'self'; object-src 'none'; base-uri 'none'; form-action 'self'; \
             frame-ancestors 'none'",
        ),
    ),
    (header::X_CONTENT_TYPE_OPTIONS, HeaderValue::from_static("nosniff")),
    (header::REFERRER_POLICY, HeaderValue::from_static("no-referrer")),
    (header::X_FRAME_OPTIONS, HeaderValue::from_static("DENY")),
];

/// The layer; give it to `Router::layer` so that it sees the matched route.
#[derive(Debug, Clone)]
pub struct Envelope {
    metrics: Arc<Metrics>,
}

impl Envelope {
    pub fn new(metrics: Arc<Metrics>) -> Self {
        Self { metrics }
    }
}

impl<S> Layer<S> for Envelope {
    type Service = Enveloped<S>;

    fn layer(&self, inner: S) -> Self::Service {
        Enveloped { inner, metrics: self.metrics.clone() }
    }
}

#[derive(Debug, Clone)]
pub struct Enveloped<S> {
    inner: S,
    metrics: Arc<Metrics>,
}

impl<S> Service<Request> for Enveloped<S>
where
    S: Service<Request, Response = Response, Error = Infallible>,
{
    type Response = Response;
    type Error = Infallible;
    type Future = Answer<S::Future>;

    fn poll_ready(&mut self, cx: &mut Context<'_>) -> Poll<Result<(), Self::Error>> {
        self.inner.poll_ready(cx)
    }

    fn call(&mut self, request: Request) -> Self::Future {
        let started = Instant::now();
        let route =
            request.extensions().get::<MatchedPath>().map_or("unmatched", MatchedPath::as_str);
        let counted = self.metrics.route(route, request.method());
        if let Some(refusal) = csrf::refusal(&request) {
            return Answer::Refused { response: Some(refusal.into_response()), started, counted };
        }
        // Kept for the 405 document; both are reference-counted views of the request head.
        let (method, uri) = (request.method().clone(), request.uri().clone());
        Answer::Served { inner: self.inner.call(request), started, counted, method, uri }
    }
}

pin_project! {
    /// The response of an enveloped request, finished on its way out.
    #[project = AnswerProjection]
    pub enum Answer<F> {
        Served {
            #[pin]
            inner: F,
            started: Instant,
            counted: Arc<RouteMetrics>,
            method: Method,
            uri: Uri,
        },
        Refused {
            response: Option<Response>,
            started: Instant,
            counted: Arc<RouteMetrics>,
        },
    }
}

impl<F> Future for Answer<F>
where
    F: Future<Output = Result<Response, Infallible>>,
{
    type Output = Result<Response, Infallible>;

    fn poll(self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<Self::Output> {
        let (mut response, started, counted) = match self.project() {
            AnswerProjection::Served { inner, started, counted, method, uri } => {
                let Ok(response) = std::task::ready!(inner.poll(cx));
                (as_problem(response, method, uri), started, counted)
            }
            AnswerProjection::Refused { response, started, counted } => (
                response.take().expect("an answer is polled until it is ready, then no more"),
                started,
                counted,
            ),
        };
        add_security_headers(response.headers_mut());
        counted.observe(response.status().as_u16(), started.elapsed().as_secs_f64());
        Poll::Ready(Ok(response))
    }
}

/// axum answers a method a route lacks with an empty 405; ours says what to do.
fn as_problem(response: Response, method: &Method, uri: &Uri) -> Response {
    if response.status() != StatusCode::METHOD_NOT_ALLOWED
        || response.headers().contains_key(CONTENT_TYPE)
    {
        return response;
    }
    // axum adds the `Allow` header after this layer has run, to our response as to its own.
    fallback::method_not_allowed(method, uri.path()).into_response()
}

fn add_security_headers(headers: &mut HeaderMap) {
    for (name, value) in &SECURITY_HEADERS {
        if !headers.contains_key(name) {
            headers.insert(name, value.clone());
        }
    }
}
