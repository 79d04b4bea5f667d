// The registry's HTTP API as the UI uses it: same-origin fetch with the session cookie, the
// anti-forgery header on every unsafe request, and problem+json turned into ApiError.

const UNSAFE = new Set(['POST', 'PUT', 'PATCH', 'DELETE']);
let csrfToken = null;

/** The session's anti-forgery token, sent as X-CSRF-Token on unsafe requests. */
export function setCsrfToken(token) {
  csrfToken = token;
}

/** An error answer of the API: status, the problem document and its field errors. */
export class ApiError extends Error {
  constructor(status, problem) {
    super(problem?.detail || problem?.title || `the registry answered ${status}`);
    this.status = status;
    this.problem = problem ?? {};
    this.errors = Array.isArray(problem?.errors) ? problem.errors : [];
  }
}

/**
 * Calls the API. Returns `{ status, data, etag, headers }`; throws ApiError on 4xx/5xx and
 * a plain Error when the registry cannot be reached. A 401 anywhere but at login announces
 * `pps:session-ended` so the app can show the login form.
 */
export async function request(method, path, { body, headers = {} } = {}) {
  const sent = { Accept: 'application/json', ...headers };
  if (body !== undefined) sent['Content-Type'] = 'application/json';
  if (UNSAFE.has(method) && csrfToken) sent['X-CSRF-Token'] = csrfToken;
  let response;
  try {
    response = await fetch(path, {
      method,
      headers: sent,
      body: body === undefined ? undefined : JSON.stringify(body),
      credentials: 'same-origin',
      cache: 'no-store',
    });
  } catch (cause) {
    throw new Error(`the registry cannot be reached (${cause.message}); check the connection and try again`);
  }
  const type = response.headers.get('Content-Type') ?? '';
  const data = type.includes('json') ? await response.json().catch(() => null) : null;
  if (!response.ok && response.status !== 304) {
    if (response.status === 401 && path !== '/api/v1/session') {
      window.dispatchEvent(new CustomEvent('pps:session-ended'));
    }
    throw new ApiError(response.status, data);
  }
  return { status: response.status, data, etag: response.headers.get('ETag'), headers: response.headers };
}

export const get = async (path) => (await request('GET', path)).data;

/** Every item of a list, following next_cursor (at most `maxPages` pages). */
export async function getAll(path, { maxPages = 20 } = {}) {
  const items = [];
  let cursor = null;
  for (let page = 0; page < maxPages; page += 1) {
    const separator = path.includes('?') ? '&' : '?';
    const url = cursor ? `${path}${separator}cursor=${encodeURIComponent(cursor)}` : path;
    const data = await get(url);
    items.push(...(data.items ?? []));
    cursor = data.next_cursor;
    if (!cursor) break;
  }
  return items;
}

/** Builds a query string from the defined, non-empty values. */
export function query(params) {
  const search = new URLSearchParams();
  for (const [key, value] of Object.entries(params)) {
    if (value !== undefined && value !== null && value !== '') search.set(key, String(value));
  }
  const text = search.toString();
  return text ? `?${text}` : '';
}

/** A path segment, escaped. */
export const seg = (text) => encodeURIComponent(text);

/** The read-only fields the registry adds to an entry, dropped before editing or comparing. */
export const READ_ONLY_FIELDS = ['epc_uri', 'revision', 'updated_at', 'updated_by', 'archived'];

/** The editable entry of a tag as GET returns it. */
export function entryOf(tag) {
  const entry = structuredClone(tag);
  for (const key of READ_ONLY_FIELDS) delete entry[key];
  return entry;
}

/** The ETag of a tag revision, as the registry writes it. */
export const etagOf = (revision) => `"r${revision}"`;
