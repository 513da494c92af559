// HTTP helpers for the SeaMap API: JSON reads, authorised writes.
// The operator token lives in localStorage (set from the panel's token field).

const TOKEN_KEY = 'seamap.token';

// The mission's prefix: "" under `seamap serve MAP`, "/missions/{id}" for a
// mission of a catalogue (`seamap serve FOLDER`), whose console is /missions/{id}/.
export const missionBase = (location.pathname.match(/^\/missions\/[a-z0-9_-]+(?=\/)/) || [''])[0];

// A server path of this mission ("/api/...", "/tiles.json") as the page asks for it.
export function missionUrl(path) {
  return path.startsWith('/') && !path.startsWith(`${missionBase}/`) ? missionBase + path : path;
}

export function getToken() {
  return localStorage.getItem(TOKEN_KEY) || '';
}

export function setToken(token) {
  if (token) localStorage.setItem(TOKEN_KEY, token);
  else localStorage.removeItem(TOKEN_KEY);
}

// Does `token` open writes? GET /api/auth answers 204 (yes, or no token is
// needed) or 401, so a wrong token is caught when it is entered, not at the
// first write. Throws ApiError when the server cannot say.
export async function checkToken(token) {
  const headers = token ? {Authorization: `Bearer ${token}`} : {};
  const response = await fetch(missionUrl('/api/auth'), {headers, cache: 'no-store'});
  if (response.status === 204) return true;
  if (response.status === 401) return false;
  throw new ApiError(response.status, `token check: ${response.status} ${response.statusText}`);
}

export class ApiError extends Error {
  constructor(status, message) {
    super(message);
    this.status = status;
  }
}

async function check(response) {
  if (response.ok) return response;
  let message = response.statusText;
  try {
    message = (await response.json()).error || message;
  } catch { /* not JSON */ }
  throw new ApiError(response.status, `${response.status} ${message}`);
}

export async function getJSON(path) {
  const response = await check(await fetch(missionUrl(path), {headers: {Accept: 'application/json'}}));
  return response.json();
}

// A collection the server answers in pages (GET /api/detections: at most
// 5000 features, and `next`, the URL of the following page): every page's
// features in one. `last_seq` stays the first page's, so nothing changed
// meanwhile is missed by the next `since`.
export async function getCollection(path) {
  const collection = await getJSON(path);
  for (let page = collection; page.next;) {
    page = await getJSON(page.next);
    for (const feature of page.features || []) collection.features.push(feature);
  }
  delete collection.next;
  return collection;
}

// POST/PATCH/DELETE with the Bearer token when one is set; null for 204.
export async function send(method, path, body) {
  const headers = {Accept: 'application/json'};
  const token = getToken();
  if (token) headers.Authorization = `Bearer ${token}`;
  if (body !== undefined) headers['Content-Type'] = 'application/json';
  const response = await check(await fetch(missionUrl(path), {
    method,
    headers,
    body: body === undefined ? undefined : JSON.stringify(body),
  }));
  return response.status === 204 ? null : response.json();
}
