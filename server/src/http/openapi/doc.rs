//! The words a route is documented in: its operation, parameters, body and replies.
//!
//! Every route of the table carries a [`Doc`], written next to its handler as a `const`, so the
//! OpenAPI document is generated from the code that serves the route and a route cannot be added
//! without one. Schemas are named, never written here: a name is a path under
//! `#/components/schemas/` (e.g. `"stored_tag"`, `"tag/$defs/epc"`).

/// What the OpenAPI document says about one route.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Doc {
    /// Unique across the API, camelCase (`listTags`).
    pub operation_id: &'static str,
    /// One line.
    pub summary: &'static str,
    /// Details a client needs beyond the summary; may be empty.
    pub description: &'static str,
    pub params: &'static [Param],
    pub body: Option<Body>,
    /// What the handler itself answers. Answers every route of its kind gives (401 and 403
    /// without the right credential, 400 for unreadable input, 413 and 415 for bodies) are
    /// added by the generator.
    pub replies: &'static [Reply],
}

impl Doc {
    pub const fn new(operation_id: &'static str, summary: &'static str) -> Self {
        Self { operation_id, summary, description: "", params: &[], body: None, replies: &[] }
    }

    pub const fn describe(mut self, description: &'static str) -> Self {
        self.description = description;
        self
    }

    pub const fn params(mut self, params: &'static [Param]) -> Self {
        self.params = params;
        self
    }

    pub const fn body(mut self, body: Body) -> Self {
        self.body = Some(body);
        self
    }

    pub const fn replies(mut self, replies: &'static [Reply]) -> Self {
        self.replies = replies;
        self
    }
}

/// Where a parameter travels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Place {
    Path,
    Query,
    Header,
}

impl Place {
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Path => "path",
            Self::Query => "query",
            Self::Header => "header",
        }
    }
}

/// The value a parameter takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ParamType {
    /// A schema of the components, by its path under `#/components/schemas/`.
    Schema(&'static str),
    Text,
    Boolean,
    Integer {
        min: i64,
        max: i64,
    },
    Uuid,
    DateTime,
    OneOf(&'static [&'static str]),
    /// Some of these values, separated by commas (`a,b`).
    SomeOf(&'static [&'static str]),
}

/// One path, query or header parameter.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Param {
    pub name: &'static str,
    pub place: Place,
    pub value: ParamType,
    pub description: &'static str,
    /// A value that works against a freshly seeded registry, for docs and API testers.
    pub example: Option<&'static str>,
}

impl Param {
    pub const fn path(name: &'static str, value: ParamType, description: &'static str) -> Self {
        Self { name, place: Place::Path, value, description, example: None }
    }

    pub const fn query(name: &'static str, value: ParamType, description: &'static str) -> Self {
        Self { name, place: Place::Query, value, description, example: None }
    }

    pub const fn header(name: &'static str, description: &'static str) -> Self {
        Self { name, place: Place::Header, value: ParamType::Text, description, example: None }
    }

    pub const fn example(mut self, example: &'static str) -> Self {
        self.example = Some(example);
        self
    }

    /// Path parameters are required; query and header parameters are optional everywhere.
    pub fn required(&self) -> bool {
        self.place == Place::Path
    }

    pub const EPC: Self = Self::path(
        "epc",
        ParamType::Schema("tag/$defs/epc"),
        "The tag's EPC: hex of whole 16-bit words, any case (also a GS1 EPC tag URI)",
    )
    .example("355AB1C60000002000000001");
    pub const ROBOT: Self =
        Self::path("robot", ParamType::Schema("robot/$defs/robot_id"), "The robot's id")
            .example("el-e-1");
    pub const TRIAL_ID: Self =
        Self::path("id", ParamType::Uuid, "The trial's UUID, chosen by the robot that made it")
            .example("0b7c2a52-4a0e-4d8e-9a51-2f7a3c1d9e10");
    pub const LIMIT: Self = Self::query(
        "limit",
        ParamType::Integer { min: 1, max: crate::http::page::MAX_LIMIT as i64 },
        "Items per page; 50 when not given",
    );
    pub const CURSOR: Self = Self::query(
        "cursor",
        ParamType::Text,
        "The `next_cursor` of the previous page, unchanged; the first page when not given",
    );
    /// On a read: the ETag the client holds, answered with 304 while it is current.
    pub const IF_NONE_MATCH_READ: Self = Self::header(
        "If-None-Match",
        "ETags the client already holds, each in double quotes (`\"r3\"`), or `*`; 304 Not \
         Modified when one is current; 400 when one is not quoted",
    );
    /// On a write: `*` to create only if nothing exists yet.
    pub const IF_NONE_MATCH_CREATE: Self = Self::header(
        "If-None-Match",
        "`*`: create the tag only if its EPC is not registered yet (412 if it is)",
    )
    .example("*");
    pub const IF_MATCH: Self = Self::header(
        "If-Match",
        "The ETag of the revision the change is based on, in double quotes as the ETag header \
         gives it (`\"r3\"`), or `*`; 412 if it is not current; 400 if it is not quoted",
    );
}

/// A request body.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Body {
    /// A schema of the components, by its path under `#/components/schemas/`.
    pub schema: &'static str,
    pub description: &'static str,
    /// Media types besides `application/json` (which every body accepts).
    pub also: &'static [&'static str],
    /// A JSON text that the route accepts.
    pub example: Option<&'static str>,
    /// Bytes of these media types instead of JSON (`schema` and `also` are then unused).
    pub binary: &'static [&'static str],
}

impl Body {
    pub const fn json(schema: &'static str, description: &'static str) -> Self {
        Self { schema, description, also: &[], example: None, binary: &[] }
    }

    /// A body of raw bytes in one of `media_types`, such as an image.
    pub const fn bytes(media_types: &'static [&'static str], description: &'static str) -> Self {
        Self { schema: "", description, also: &[], example: None, binary: media_types }
    }

    pub const fn also(mut self, media_types: &'static [&'static str]) -> Self {
        self.also = media_types;
        self
    }

    pub const fn example(mut self, json: &'static str) -> Self {
        self.example = Some(json);
        self
    }
}

/// What a reply carries.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Content {
    /// `application/json` of a schema of the components.
    Json(&'static str),
    /// `application/json` list page (`{"items", "next_cursor"}`) of a schema of the components:
    /// the component `<item>_page`, which `components.rs` derives from `Page<item's type>`.
    Page(&'static str),
    /// `application/problem+json`.
    Problem,
    /// `text/plain`.
    Text,
    /// `text/event-stream`.
    EventStream,
    /// Raw bytes in one of these media types, such as an image.
    Bytes(&'static [&'static str]),
    Empty,
}

/// A response header worth documenting.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Header {
    ETag,
    Location,
    SetCookie,
    RetryAfter,
    CacheControl,
    /// How long a private cache may keep an answer that never changes once stored.
    CacheControlPrivate,
}

impl Header {
    pub fn name(self) -> &'static str {
        match self {
            Self::ETag => "ETag",
            Self::Location => "Location",
            Self::SetCookie => "Set-Cookie",
            Self::RetryAfter => "Retry-After",
            Self::CacheControl | Self::CacheControlPrivate => "Cache-Control",
        }
    }

    pub fn description(self) -> &'static str {
        match self {
            Self::ETag => {
                "The strong validator of what was returned, for If-None-Match and If-Match"
            }
            Self::Location => "Where the created resource lives",
            Self::SetCookie => "The session cookie (HttpOnly, SameSite=Strict)",
            Self::RetryAfter => "Seconds to wait before trying again",
            Self::CacheControl => "`no-store`: answers about credentials are never cached",
            Self::CacheControlPrivate => {
                "`private, max-age=...`: the browser may keep it; shared caches may not"
            }
        }
    }
}

/// One status a route answers with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Reply {
    pub status: u16,
    pub description: &'static str,
    pub content: Content,
    pub headers: &'static [Header],
}

impl Reply {
    pub const fn json(status: u16, description: &'static str, schema: &'static str) -> Self {
        Self { status, description, content: Content::Json(schema), headers: &[] }
    }

    pub const fn page(description: &'static str, item_schema: &'static str) -> Self {
        Self { status: 200, description, content: Content::Page(item_schema), headers: &[] }
    }

    pub const fn problem(status: u16, description: &'static str) -> Self {
        Self { status, description, content: Content::Problem, headers: &[] }
    }

    pub const fn empty(status: u16, description: &'static str) -> Self {
        Self { status, description, content: Content::Empty, headers: &[] }
    }

    pub const fn text(status: u16, description: &'static str) -> Self {
        Self { status, description, content: Content::Text, headers: &[] }
    }

    pub const fn bytes(
        status: u16,
        description: &'static str,
        media_types: &'static [&'static str],
    ) -> Self {
        Self { status, description, content: Content::Bytes(media_types), headers: &[] }
    }

    pub const fn event_stream(description: &'static str) -> Self {
        Self { status: 200, description, content: Content::EventStream, headers: &[] }
    }

    pub const fn headers(mut self, headers: &'static [Header]) -> Self {
        self.headers = headers;
        self
    }

    pub const NOT_MODIFIED: Self =
        Self::empty(304, "Not Modified: the If-None-Match ETag is current")
            .headers(&[Header::ETag]);
    pub const PRECONDITION_FAILED: Self = Self::problem(
        412,
        "Precondition Failed: the If-Match or If-None-Match condition does not hold",
    );
    pub const PRECONDITION_REQUIRED: Self = Self::problem(
        428,
        "Precondition Required: a write without If-Match (or If-None-Match: * to create)",
    );
    pub const INVALID: Self = Self::problem(
        422,
        "The body is not valid: `errors` lists every problem with its JSON pointer",
    );
}
