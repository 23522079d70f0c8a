// SPDX-License-Identifier: MIT
// The client of depathd's JSON API (/v1): one function per call. Adds the bearer token the
// user typed (kept in sessionStorage only) and turns error answers into Error objects with
// the HTTP status and the server's message.

const TOKEN_KEY = 'depath.token';

export function token() {
  return sessionStorage.getItem(TOKEN_KEY) || '';
}

export function setToken(value) {
  if (value) sessionStorage.setItem(TOKEN_KEY, value);
  else sessionStorage.removeItem(TOKEN_KEY);
}

export function authHeaders(extra = {}) {
  const headers = { ...extra };
  const t = token();
  if (t) headers.Authorization = `Bearer ${t}`;
  return headers;
}

export class ApiError extends Error {
  constructor(status, message) {
    super(message);
    this.status = status;
  }
}

async function call(method, path, { body, headers = {} } = {}) {
  const response = await fetch(path, { method, body, headers: authHeaders(headers) });
  if (!response.ok) {
    let message = `${response.status} ${response.statusText}`;
    try {
      const text = await response.text();
      try {
        const j = JSON.parse(text);
        message = j.message || (j.error && (j.error.message || j.error)) || text || message;
      } catch {
        if (text) message = text;
      }
    } catch {
      // keep the status line
    }
    throw new ApiError(response.status, message);
  }
  return response.json();
}

export const listJobs = () => call('GET', '/v1/jobs');
export const getJob = (id) => call('GET', `/v1/jobs/${encodeURIComponent(id)}`);
export const getProgress = (id) => call('GET', `/v1/jobs/${encodeURIComponent(id)}/progress`);
export const getField = (id) => call('GET', `/v1/jobs/${encodeURIComponent(id)}/field`);
export const getGeometry = (meshId) => call('GET', `/v1/meshes/${encodeURIComponent(meshId)}/geometry`);
export const cancelJob = (id) => call('POST', `/v1/jobs/${encodeURIComponent(id)}/cancel`);
export const submitJob = (spec) =>
  call('POST', '/v1/jobs', { body: JSON.stringify(spec), headers: { 'Content-Type': 'application/json' } });
export const uploadMesh = (bytes, format) =>
  call('POST', `/v1/meshes?format=${encodeURIComponent(format)}`, {
    body: bytes,
    headers: { 'Content-Type': 'application/octet-stream' },
  });

/// Download links of a finished job's result, by format.
export function resultUrl(id, format) {
  return `/v1/jobs/${encodeURIComponent(id)}/result.${format}`;
}
