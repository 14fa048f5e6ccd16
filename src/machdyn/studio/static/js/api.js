// The API client: every answer comes from the server (the page computes no physics).

export class ApiError extends Error {
  constructor(message, status, key) {
    super(message);
    this.status = status;
    this.key = key || null;
  }
}

export async function post(call, body) {
  let response;
  try {
    response = await fetch("/api/" + call, {
      method: "POST",
      headers: { "Content-Type": "application/json" },
      body: JSON.stringify(body),
    });
  } catch (err) {
    throw new ApiError("the studio's server does not answer (was it stopped?)", 0);
  }
  const type = response.headers.get("Content-Type") || "";
  if (!response.ok) {
    let message = `HTTP ${response.status}`;
    let key = null;
    if (type.startsWith("application/json")) {
      const data = await response.json();
      message = data.error || message;
      key = data.key;
    }
    throw new ApiError(message, response.status, key);
  }
  if (type.startsWith("application/json")) return response.json();
  const name = /filename="([^"]+)"/.exec(response.headers.get("Content-Disposition") || "");
  return { blob: await response.blob(), filename: name ? name[1] : "machdyn" };
}

// Analysis requests while dragging: one in flight; only the newest waiting one is sent next.
export class Analyst {
  constructor(onResult, onError) {
    this.onResult = onResult;
    this.onError = onError;
    this.busy = false;
    this.waiting = null;
  }

  request(body, tag) {
    this.waiting = { body: JSON.stringify(body), tag };
    if (!this.busy) this.next();
  }

  async next() {
    const job = this.waiting;
    this.waiting = null;
    if (!job) return;
    this.busy = true;
    let data = null, error = null;
    try {
      const response = await fetch("/api/analyse", {
        method: "POST", headers: { "Content-Type": "application/json" }, body: job.body,
      });
      const timing = response.headers.get("Server-Timing") || "";
      const server = /app;dur=([\d.]+)/.exec(timing), cpu = /cpu;dur=([\d.]+)/.exec(timing);
      data = await response.json().catch(() => ({ error: `HTTP ${response.status}` }));
      job.tag.server = server ? Number(server[1]) : null;
      job.tag.cpu = cpu ? Number(cpu[1]) : null;
      job.tag.received = performance.now();
      if (!response.ok) error = new ApiError(data.error || `HTTP ${response.status}`, response.status, data.key);
      else if (data.refused) error = new ApiError(data.refused, 200, data.key);
    } catch (err) {
      error = new ApiError("the studio's server does not answer (was it stopped?)", 0);
    }
    this.busy = false;
    try {
      if (error) this.onError(error, job.tag); else this.onResult(data, job.tag);
    } finally {
      if (this.waiting) this.next();
    }
  }
}
