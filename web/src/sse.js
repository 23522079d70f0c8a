// SPDX-License-Identifier: MIT
// Reads a Server-Sent Events stream with fetch() (EventSource cannot send the bearer token)
// and a small parser of the text/event-stream format. Reconnects after a drop with
// Last-Event-ID so no numbered event is missed; stops when told or when the server ends the
// stream after a job's final event.

import { authHeaders, ApiError } from './api.js';

/// Parses complete events out of `buffer`; returns [events, rest]. An event is
/// {id, event, data} with `data` the joined data lines (a string).
export function parseEvents(buffer) {
  const events = [];
  const normalized = buffer.replace(/\r\n?/g, '\n');
  const blocks = normalized.split('\n\n');
  const rest = blocks.pop();
  for (const block of blocks) {
    const ev = { id: null, event: 'message', data: [] };
    for (const line of block.split('\n')) {
      if (line === '' || line.startsWith(':')) continue;
      const colon = line.indexOf(':');
      const field = colon < 0 ? line : line.slice(0, colon);
      let value = colon < 0 ? '' : line.slice(colon + 1);
      if (value.startsWith(' ')) value = value.slice(1);
      if (field === 'id') ev.id = value;
      else if (field === 'event') ev.event = value;
      else if (field === 'data') ev.data.push(value);
    }
    if (ev.data.length || ev.id !== null) events.push({ ...ev, data: ev.data.join('\n') });
  }
  return [events, rest];
}

/// Follows `url`; calls onEvent({id, event, data: parsed JSON}) for each event. Returns a
/// function that stops it. `isFinal(ev)` tells when no more events will come.
export function followEvents(url, { onEvent, onError = () => {}, isFinal = () => false, retryMs = 1000 }) {
  let lastId = null;
  let stopped = false;
  let controller = null;
  let finished = false;

  const connect = async () => {
    while (!stopped && !finished) {
      controller = new AbortController();
      try {
        const headers = authHeaders({ Accept: 'text/event-stream' });
        if (lastId !== null) headers['Last-Event-ID'] = lastId;
        const response = await fetch(url, { headers, signal: controller.signal, cache: 'no-store' });
        if (!response.ok) {
          const text = await response.text().catch(() => '');
          throw new ApiError(response.status, text || `${response.status} ${response.statusText}`);
        }
        const reader = response.body.getReader();
        const decoder = new TextDecoder();
        let buffer = '';
        for (;;) {
          const { value, done } = await reader.read();
          if (done) break;
          buffer += decoder.decode(value, { stream: true });
          const [events, rest] = parseEvents(buffer);
          buffer = rest;
          for (const ev of events) {
            if (ev.id !== null) lastId = ev.id;
            let data = null;
            try {
              data = ev.data ? JSON.parse(ev.data) : null;
            } catch {
              data = ev.data;
            }
            const parsed = { id: ev.id, event: ev.event, data, receivedAt: performance.now() };
            onEvent(parsed);
            if (isFinal(parsed)) finished = true;
          }
        }
        if (finished) break;
      } catch (err) {
        if (stopped) break;
        onError(err);
        // Unauthorized or unknown job: reconnecting will not help.
        if (err instanceof ApiError && err.status >= 400 && err.status < 500) break;
      }
      if (!stopped && !finished) await new Promise((r) => setTimeout(r, retryMs));
    }
  };
  connect();
  return () => {
    stopped = true;
    if (controller) controller.abort();
  };
}
