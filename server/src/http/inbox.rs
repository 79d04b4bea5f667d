//! `GET /api/v1/inbox`: EPCs robots read that nobody registered.

use axum::Json;
use axum::extract::State;

use crate::answers::inbox::InboxAnswer;
use crate::error::ApiError;
use crate::http::extract::ApiQuery;
use crate::http::openapi::doc::{Doc, Param, Reply};
use crate::http::page::{self, Page, PageParams};
use crate::state::AppState;
use crate::store::inbox;

pub const LIST: Doc = Doc::new("listInbox", "EPCs robots read that nobody registered")
    .params(&[Param::LIMIT, Param::CURSOR])
    .replies(&[Reply::page("A page of unknown EPCs, by EPC", "inbox_item")]);

pub async fn list(
    State(state): State<AppState>,
    ApiQuery(params): ApiQuery<PageParams>,
) -> Result<Json<Page<InboxAnswer>>, ApiError> {
    let limit = page::limit(params.limit)?;
    let after = params.cursor.as_deref().map(page::decode_cursor).transpose()?;
    let rows = inbox::list(state.db.reader(), after.as_deref(), limit + 1).await?;
    Ok(Json(page::page(rows, limit, |item| item.epc.clone()).map(InboxAnswer::from)))
}
