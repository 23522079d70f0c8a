// SPDX-License-Identifier: MIT
// Entry point: routes / to the job list and /jobs/{id} to a job's page, shows status
// messages, and asks for the bearer token when the server answers 401.

import './style.css';
import * as api from './api.js';
import { h } from './dom.js';
import { renderJobList } from './job_list.js';
import { renderJobPage } from './job_page.js';

const app = document.getElementById('app');
const statusEl = document.getElementById('status');
let leave = null;

function tokenForm() {
  const input = h('input', { type: 'password', id: 'token', placeholder: 'bearer token', value: api.token() });
  return h('form', { id: 'token-form', onsubmit: (e) => { e.preventDefault(); api.setToken(input.value.trim()); route(); } },
    'This server needs a token: ', input, ' ', h('button', { type: 'submit' }, 'Use token'));
}

function status(message, isError = false, askToken = false) {
  statusEl.replaceChildren(message ? h('span', { class: isError ? 'error' : '' }, message) : '');
  if (askToken) statusEl.append(' ', tokenForm());
}

function route() {
  if (leave) leave();
  status('');
  const match = location.pathname.match(/^\/jobs\/([^/]+)\/?$/);
  if (match) {
    const id = decodeURIComponent(match[1]);
    document.title = `depath job ${id}`;
    leave = renderJobPage(app, id, status);
  } else {
    document.title = 'depath jobs';
    leave = renderJobList(app, status);
  }
}

window.addEventListener('popstate', route);
route();
