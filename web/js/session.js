// Who is logged in: the session the registry reports, kept for the pages and the API client.

import { request, setCsrfToken } from './api.js';

let current = null;

/** The logged-in user `{ name, role, credential }`, or null. */
export const user = () => current;
export const isAdmin = () => current?.role === 'admin';

function adopt(data) {
  current = data;
  setCsrfToken(data?.csrf_token ?? null);
  return data;
}

/** Asks the registry who this browser is; null when nobody is logged in. */
export async function load() {
  try {
    return adopt((await request('GET', '/api/v1/session')).data);
  } catch (error) {
    if (error.status === 401) return adopt(null);
    throw error;
  }
}

/** Logs in; throws ApiError (401 wrong password, 429 slowed down). */
export async function login(username, password) {
  return adopt((await request('POST', '/api/v1/session', { body: { username, password } })).data);
}

export async function logout() {
  try {
    await request('DELETE', '/api/v1/session');
  } finally {
    adopt(null);
  }
}

/** Forgets the session locally (the registry already ended it). */
export const forget = () => adopt(null);
