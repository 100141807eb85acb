// The server's JSON API (docs/viewer.md, "The HTTP API"): every call resolves to the parsed body or
// throws an ApiError carrying the server's one-line message and, if one field was at fault, its name.

import { tr } from './i18n.js';

export class ApiError extends Error {
  constructor(message, status, field) {
    super(message);
    this.status = status;
    this.field = field || null;
  }
}

// A frame answer with buffers: 4 bytes (little-endian) of JSON length, the JSON, spaces to a multiple
// of 4 bytes, then the arrays the JSON points into as {"array": "float32"|"uint32", "offset", "length"}.
const FRAME_WITH_ARRAYS = 'application/vnd.hsr.frame';
const ARRAY_TYPES = { float32: Float32Array, uint32: Uint32Array };

// The answer's JSON with each array reference replaced by a typed array over the bytes (no copy:
// every browser the page runs on is little-endian, like the server's arrays).
export function decodeFrameAnswer(buffer) {
  const length = new DataView(buffer).getUint32(0, true);
  const text = new TextDecoder().decode(new Uint8Array(buffer, 4, length));
  const base = Math.ceil((4 + length) / 4) * 4;
  return JSON.parse(text, (key, value) => {
    if (value && typeof value === 'object' && !Array.isArray(value) && ARRAY_TYPES[value.array]) {
      return new ARRAY_TYPES[value.array](buffer, base + value.offset, value.length);
    }
    return value;
  });
}

async function call(path, options) {
  let response;
  try {
    response = await fetch(path, options);
  } catch (e) {
    throw new ApiError(tr({ en: `the server does not answer (${e.message})`, ru: `сервер не отвечает (${e.message})` }), 0, null);
  }
  if (response.ok && (response.headers.get('Content-Type') || '').startsWith(FRAME_WITH_ARRAYS)) {
    return decodeFrameAnswer(await response.arrayBuffer());
  }
  let body = null;
  const text = await response.text();
  try {
    body = text ? JSON.parse(text) : null;
  } catch {
    body = null;
  }
  if (!response.ok) {
    const message = body && typeof body.error === 'string' ? body.error
      : `${path}: HTTP ${response.status}`;
    throw new ApiError(message, response.status, body && body.field);
  }
  if (body === null || typeof body !== 'object') {
    throw new ApiError(tr({ en: `${path}: the answer is not JSON`, ru: `${path}: ответ не в формате JSON` }), response.status, null);
  }
  return body;
}

export const getJson = (path) => call(path, { headers: { Accept: 'application/json' } });

// This page's name for the server: a newer frame from the same page cancels the one before.
const PAGE_ID = (crypto.randomUUID && crypto.randomUUID()) || `${Date.now()}-${Math.random().toString(36).slice(2)}`;

export const postJson = (path, value) => call(path, {
  method: 'POST',
  headers: { 'Content-Type': 'application/json', Accept: 'application/json', 'X-HSR-Page': PAGE_ID },
  body: JSON.stringify(value),
});

// A request beside the page's frames, under a name of its own: it cancels none of them (and a
// newer one cancels the one before).
export const postJsonAside = (path, value) => call(path, {
  method: 'POST',
  headers: { 'Content-Type': 'application/json', Accept: 'application/json', 'X-HSR-Page': `${PAGE_ID}-aside` },
  body: JSON.stringify(value),
});

// A file the server makes for the page to save (POST /api/steps-zip): {blob, name}, the name from
// the answer's Content-Disposition; an error answer throws an ApiError as call() does.
export async function postForFile(path, value, fallbackName) {
  let response;
  try {
    response = await fetch(path, {
      method: 'POST',
      headers: { 'Content-Type': 'application/json', 'X-HSR-Page': PAGE_ID },
      body: JSON.stringify(value),
    });
  } catch (e) {
    throw new ApiError(tr({ en: `the server does not answer (${e.message})`, ru: `сервер не отвечает (${e.message})` }), 0, null);
  }
  if (!response.ok) {
    let body = null;
    try {
      body = await response.json();
    } catch {
      body = null;
    }
    throw new ApiError(body && typeof body.error === 'string' ? body.error : `${path}: HTTP ${response.status}`,
      response.status, body && body.field);
  }
  const disposition = response.headers.get('Content-Disposition') || '';
  const match = /filename="([^"]+)"/.exec(disposition);
  return { blob: await response.blob(), name: match ? match[1] : fallbackName };
}

// How far this page's frame in flight has got: {running, ms, progress: {steps, total} or null}.
export const getProgress = () => call('/api/progress', { headers: { Accept: 'application/json', 'X-HSR-Page': PAGE_ID } });

// Stops this page's frame in flight: it ends with an ApiError of status 409.
export const cancelFrame = () => call('/api/cancel', {
  method: 'POST',
  headers: { 'Content-Type': 'application/json', Accept: 'application/json', 'X-HSR-Page': PAGE_ID },
  body: '{}',
});

export const uploadModel = (file) => call('/api/upload', {
  method: 'POST',
  headers: { 'X-File-Name': file.name, 'Content-Type': 'application/octet-stream' },
  body: file,
});

// `value` if it is a typed array of that kind (an array of a frame answer), else null.
export function typedArray(value, ArrayType) {
  return value instanceof ArrayType ? value : null;
}
