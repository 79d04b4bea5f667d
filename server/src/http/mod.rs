//! The HTTP API: one route table, read top to bottom, with each route's access next to it.

pub mod access;
mod csrf;
mod effective;
mod envelope;
mod events;
pub mod extract;
mod fallback;
mod home_assistant;
pub mod ids;
mod inbox;
mod meta;
pub mod openapi;
pub mod page;
pub mod pictures;
pub mod precondition;
mod retag;
mod robots;
mod session;
mod stats;
mod tags;
pub(crate) mod tasks;
mod tokens;
mod trials;
mod typed_json;
mod users;
mod web;

use axum::Router;
use axum::extract::DefaultBodyLimit;
use axum::handler::Handler;
use axum::http::Method;
use axum::routing::{MethodFilter, on};

pub use access::Access;
use openapi::accounts;
use openapi::doc::Doc;

use crate::state::AppState;

/// One route of the API, as the role table and the OpenAPI document see it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RouteSpec {
    pub method: Method,
    pub path: &'static str,
    pub access: Access,
    pub doc: Doc,
}

/// The API's routes; every one goes through [`Routes::add`], so none escapes the access check
/// or the OpenAPI document.
struct Routes {
    state: AppState,
    router: Router<AppState>,
    specs: Vec<RouteSpec>,
}

impl Routes {
    fn add<H, T>(
        mut self,
        method: Method,
        path: &'static str,
        access: Access,
        handler: H,
        doc: Doc,
    ) -> Self
    where
        H: Handler<T, AppState>,
        T: 'static,
    {
        let filter = MethodFilter::try_from(method.clone()).expect("a standard method");
        let gate = access::Gate::new(self.state.clone(), access);
        self.router = self.router.route(path, on(filter, handler).route_layer(gate));
        self.specs.push(RouteSpec { method, path, access, doc });
        self
    }
}

/// The whole application: API, UI and the layers every response passes through.
pub fn router(state: AppState) -> Router {
    router_with_routes(state).0
}

/// The application and the table of its API routes.
pub fn router_with_routes(state: AppState) -> (Router, Vec<RouteSpec>) {
    use Access::*;
    let get = || Method::GET;
    let openapi = openapi::Published::default();
    let routes = Routes { state: state.clone(), router: Router::new(), specs: Vec::new() }
        .add(get(), "/healthz", Open, meta::healthz, meta::HEALTHZ)
        .add(get(), "/readyz", Open, meta::readyz, meta::READYZ)
        .add(get(), "/api/v1/openapi.json", Open, openapi.handler(), openapi::DOC)
        .add(get(), "/api/v1/schema/{name}", Open, meta::schema, meta::SCHEMA)
        .add(get(), "/api/v1/tags", Anyone, tags::list, tags::LIST)
        .add(get(), "/api/v1/tags/{epc}", Anyone, tags::get, tags::GET)
        .add(Method::PUT, "/api/v1/tags/{epc}", Editors, tags::put, tags::PUT)
        .add(Method::DELETE, "/api/v1/tags/{epc}", Editors, tags::archive, tags::ARCHIVE)
        .add(get(), "/api/v1/tags/{epc}/revisions", Editors, tags::revisions, tags::REVISIONS)
        .add(get(), "/metrics", Open, meta::metrics, meta::METRICS)
        .add(get(), "/api/v1/tags/{epc}/stats", Anyone, stats::get, stats::GET)
        .add(
            get(),
            "/api/v1/tags/{epc}/picture",
            Editors,
            pictures::newest_of_tag,
            pictures::TAG_GET,
        )
        .add(Method::POST, "/api/v1/tags/{epc}/retag", Editors, retag::retag, retag::RETAG)
        .add(Method::POST, "/api/v1/validate/tag", Editors, tags::validate, tags::VALIDATE)
        .add(get(), "/api/v1/robots", Anyone, robots::list, robots::LIST)
        .add(get(), "/api/v1/robots/{robot}", Anyone, robots::get, robots::GET)
        .add(Method::PUT, "/api/v1/robots/{robot}", Admin, robots::put, robots::PUT)
        .add(
            get(),
            "/api/v1/robots/{robot}/tags/{epc}",
            RobotOrEditors,
            effective::get,
            effective::GET,
        )
        .add(get(), "/api/v1/inbox", Editors, inbox::list, inbox::LIST)
        .add(Method::PUT, "/api/v1/trials/{id}", Robot, trials::put, trials::PUT)
        .add(get(), "/api/v1/trials/{id}", RobotOrEditors, trials::get, trials::GET)
        .add(Method::PATCH, "/api/v1/trials/{id}", RobotOrEditors, trials::patch, trials::PATCH)
        .add(get(), "/api/v1/trials", RobotOrEditors, trials::list, trials::LIST)
        .add(Method::PUT, "/api/v1/trials/{id}/picture", Robot, pictures::put, pictures::PUT)
        .add(get(), "/api/v1/trials/{id}/picture", RobotOrEditors, pictures::get, pictures::GET)
        .add(get(), "/api/v1/events", Anyone, events::stream, events::STREAM)
        .add(Method::POST, "/api/v1/tasks", Editors, tasks::create, tasks::CREATE)
        .add(get(), "/api/v1/tasks", RobotOrEditors, tasks::list, tasks::LIST)
        .add(get(), "/api/v1/tasks/{id}", RobotOrEditors, tasks::get, tasks::GET)
        .add(Method::POST, "/api/v1/tasks/{id}/cancel", Editors, tasks::cancel, tasks::CANCEL)
        .add(
            Method::POST,
            "/api/v1/robots/{robot}/tasks/claim",
            Robot,
            tasks::lease::claim,
            tasks::lease::CLAIM,
        )
        .add(
            Method::POST,
            "/api/v1/tasks/{id}/heartbeat",
            Robot,
            tasks::lease::heartbeat,
            tasks::lease::HEARTBEAT,
        )
        .add(
            Method::POST,
            "/api/v1/tasks/{id}/finish",
            Robot,
            tasks::lease::finish,
            tasks::lease::FINISH,
        )
        .add(
            Method::POST,
            "/api/v1/tasks/{id}/decline",
            Robot,
            tasks::decline::decline,
            tasks::decline::DECLINE,
        )
        .add(get(), "/api/v1/home-assistant", Admin, home_assistant::get, home_assistant::GET)
        .add(get(), "/api/v1/tokens", Admin, tokens::list, tokens::LIST)
        .add(Method::POST, "/api/v1/tokens", Admin, tokens::create, tokens::CREATE)
        .add(Method::DELETE, "/api/v1/tokens/{id}", Admin, tokens::revoke, tokens::REVOKE)
        .add(Method::POST, "/api/v1/session", Open, session::login, accounts::LOGIN)
        .add(get(), "/api/v1/session", Anyone, session::current, accounts::CURRENT_SESSION)
        .add(Method::DELETE, "/api/v1/session", Anyone, session::logout, accounts::LOGOUT)
        .add(get(), "/api/v1/users", Admin, users::list, accounts::USERS)
        .add(Method::POST, "/api/v1/users", Admin, users::create, accounts::CREATE_USER)
        .add(Method::DELETE, "/api/v1/users/{name}", Admin, users::delete, accounts::DELETE_USER)
        .add(
            Method::PUT,
            "/api/v1/users/{name}/password",
            Anyone,
            users::set_password,
            accounts::SET_PASSWORD,
        );
    let Routes { router, specs, .. } = routes;
    openapi.publish(&specs);
    // One `layer` call, so each route is wrapped (and boxed by axum) once, not per layer.
    let every_request = tower::ServiceBuilder::new()
        .layer(crate::ops::telemetry::http_trace_layer())
        .layer(envelope::Envelope::new(state.metrics.clone()))
        .layer(DefaultBodyLimit::max(extract::MAX_BODY_BYTES));
    let router = router
        .merge(web::router())
        .fallback(fallback::not_found)
        .layer(every_request)
        .with_state(state);
    (router, specs)
}
