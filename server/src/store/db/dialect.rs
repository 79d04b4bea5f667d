//! The two SQL dialects the store speaks. Most statements are written once in the SQL both
//! engines share (`$1` parameters, `on conflict`, `returning`, `coalesce`, `case`); the few
//! that need an engine's own functions (JSON inside a stored document, string aggregation) are
//! written once per engine, side by side, through [`Dialect::pick`].

use sqlx::AnyConnection;
use sqlx::AnyPool;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dialect {
    Sqlite,
    Postgres,
}

impl Dialect {
    /// The dialect of an open connection.
    pub fn of(conn: &AnyConnection) -> Self {
        Self::named(conn.backend_name())
    }

    /// The dialect of a pool's connections.
    pub fn of_pool(pool: &AnyPool) -> Self {
        let options = pool.connect_options();
        if options.database_url.scheme().starts_with("postgres") {
            Self::Postgres
        } else {
            Self::Sqlite
        }
    }

    fn named(backend: &str) -> Self {
        if backend == "PostgreSQL" { Self::Postgres } else { Self::Sqlite }
    }

    /// The statement written for this engine.
    pub fn pick(self, sqlite: &'static str, postgres: &'static str) -> &'static str {
        match self {
            Self::Sqlite => sqlite,
            Self::Postgres => postgres,
        }
    }
}
