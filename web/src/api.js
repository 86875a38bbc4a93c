// The service's documented endpoints (proto/openapi.json, also at /openapi.json), from the page's origin.
// The bearer token, when the service asks for one (401), lives only in this module's memory: never stored.
let token = '';
let askToken = null;  // async () => token, set by the page

export function setTokenPrompt(prompt) { askToken = prompt; }
export function hasToken() { return token !== ''; }

function headers(extra = {}) {
  return token ? { ...extra, Authorization: `Bearer ${token}` } : extra;
}

// An API error as the page shows it: HTTP status, error.code, error.message (the service's one error body).
export class ApiError extends Error {
  constructor(status, code, message, details) {
    super(message);
    this.status = status; this.code = code; this.details = details || {};
  }
}

function errorFrom(status, text) {
  try {
    const body = JSON.parse(text);
    if (body && body.error) return new ApiError(status, body.error.code, body.error.message, body.error.details);
  } catch { /* not JSON */ }
  return new ApiError(status, `http_${status}`, text ? text.slice(0, 200) : `HTTP ${status}`);
}

async function withAuth(run) {
  for (let attempt = 0; attempt < 3; ++attempt) {
    try {
      return await run();
    } catch (e) {
      if (!(e instanceof ApiError) || e.status !== 401 || !askToken) throw e;
      token = await askToken(attempt > 0);
    }
  }
  return run();
}

export async function getJson(path) {
  return withAuth(async () => {
    const r = await fetch(path, { headers: headers() });
    const text = await r.text();
    if (!r.ok) throw errorFrom(r.status, text);
    return JSON.parse(text);
  });
}

// POST one mesh file as the raw body (the service detects the format). onProgress(fraction uploaded, phase).
// `accept(status, body)`: whether a non-200 answer is a result (a label volume's 207, or its 4xx that still lists
// every object) rather than an error.
export function postMesh(path, file, onProgress, accept = () => false) {
  return withAuth(() => new Promise((resolve, reject) => {
    const xhr = new XMLHttpRequest();
    xhr.open('POST', path);
    for (const [k, v] of Object.entries(headers({ 'Content-Type': 'application/octet-stream' }))) xhr.setRequestHeader(k, v);
    xhr.upload.onprogress = (e) => { if (e.lengthComputable) onProgress(e.loaded / e.total, 'uploading'); };
    xhr.upload.onload = () => onProgress(1, 'computing');
    xhr.onerror = () => reject(new ApiError(0, 'network_error', 'the service could not be reached'));
    xhr.onload = () => {
      let body = null;
      try { body = JSON.parse(xhr.responseText); } catch { /* not JSON: an error below */ }
      if (xhr.status === 200 || (body && accept(xhr.status, body))) {
        if (body) resolve(body); else reject(new ApiError(xhr.status, 'bad_json', 'the answer is not JSON'));
      } else {
        reject(errorFrom(xhr.status, xhr.responseText));
      }
    };
    xhr.send(file);
  }));
}
