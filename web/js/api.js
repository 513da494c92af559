// HTTP helpers for the SeaMap API: JSON reads, authorised writes.
// The operator token lives in localStorage (set from the panel's token field).

const TOKEN_KEY = 'seamap.token';

export function getToken() {
  return localStorage.getItem(TOKEN_KEY) || '';
}

export function setToken(token) {
  if (token) localStorage.setItem(TOKEN_KEY, token);
  else localStorage.removeItem(TOKEN_KEY);
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
  const response = await check(await fetch(path, {headers: {Accept: 'application/json'}}));
  return response.json();
}

// POST/PATCH/DELETE with the Bearer token when one is set; null for 204.
export async function send(method, path, body) {
  const headers = {Accept: 'application/json'};
  const token = getToken();
  if (token) headers.Authorization = `Bearer ${token}`;
  if (body !== undefined) headers['Content-Type'] = 'application/json';
  const response = await check(await fetch(path, {
    method,
    headers,
    body: body === undefined ? undefined : JSON.stringify(body),
  }));
  return response.status === 204 ? null : response.json();
}
