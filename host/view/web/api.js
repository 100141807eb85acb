// The server's JSON API (docs/viewer.md, "The HTTP API"): every call resolves to the parsed body or
// throws an ApiError carrying the server's one-line message and, if one field was at fault, its name.

export class ApiError extends Error {
  constructor(message, status, field) {
    super(message);
    this.status = status;
    this.field = field || null;
  }
}

async function call(path, options) {
  let response;
  try {
    response = await fetch(path, options);
  } catch (e) {
    throw new ApiError(`the server does not answer (${e.message})`, 0, null);
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
    throw new ApiError(`${path}: the answer is not JSON`, response.status, null);
  }
  return body;
}

export const getJson = (path) => call(path, { headers: { Accept: 'application/json' } });

export const postJson = (path, value) => call(path, {
  method: 'POST',
  headers: { 'Content-Type': 'application/json', Accept: 'application/json' },
  body: JSON.stringify(value),
});

export const uploadModel = (file) => call('/api/upload', {
  method: 'POST',
  headers: { 'X-File-Name': file.name, 'Content-Type': 'application/octet-stream' },
  body: file,
});

// Base64 of a little-endian array (the server's `buffers`) to a typed array of the given kind.
export function decodeArray(base64, ArrayType) {
  if (typeof base64 !== 'string') return null;
  const binary = atob(base64);
  const bytes = new Uint8Array(binary.length);
  for (let i = 0; i < binary.length; ++i) bytes[i] = binary.charCodeAt(i);
  const elements = Math.floor(bytes.byteLength / ArrayType.BYTES_PER_ELEMENT);
  // Every browser the page runs on is little-endian, like the server's arrays.
  return new ArrayType(bytes.buffer, 0, elements);
}
