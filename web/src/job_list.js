// SPDX-License-Identifier: MIT
// The front page (/): every job with its live state and progress (refreshed every two seconds
// while the page is open), and the new-job form.

import * as api from './api.js';
import { h, formatNumber, navigate } from './dom.js';
import { renderSubmitForm } from './submit_form.js';

export function renderJobList(root, status) {
  const tbody = h('tbody', { id: 'jobs' });
  const table = h('table', { class: 'jobs' },
    h('thead', {}, h('tr', {}, ...['job', 'state', 'mesh', 'energy', 'method', 'generation', 'best energy', 'created']
      .map((c) => h('th', {}, c)))),
    tbody);
  root.replaceChildren(h('h1', {}, 'depath jobs'), table, renderSubmitForm(status));

  const row = (j) => {
    const link = h('a', { href: `/jobs/${encodeURIComponent(j.id)}`, class: 'job-link',
      onclick: (e) => { e.preventDefault(); navigate(`/jobs/${encodeURIComponent(j.id)}`); } }, j.id);
    const progress = j.generations ? `${j.generation ?? 0} / ${j.generations}` : formatNumber(j.generation);
    return h('tr', { dataset: { jobId: j.id, state: j.state } },
      h('td', {}, link), h('td', { class: `state state-${j.state}` }, j.state),
      h('td', { title: j.mesh_id }, (j.mesh_id || '').slice(0, 12)), h('td', {}, j.energy ?? ''), h('td', {}, j.method ?? ''),
      h('td', {}, progress), h('td', {}, formatNumber(j.best_energy)),
      h('td', {}, j.created_at ? new Date(typeof j.created_at === 'number' ? j.created_at * 1000 : j.created_at).toLocaleString() : ''));
  };

  let timer = null;
  let stopped = false;
  const refresh = async () => {
    try {
      const { jobs } = await api.listJobs();
      tbody.replaceChildren(...(jobs.length ? jobs.map(row) : [h('tr', {}, h('td', { colspan: 8 }, 'No jobs yet.'))]));
    } catch (e) {
      status(`Cannot list jobs: ${e.message}`, true, e.status === 401);
    }
    if (!stopped) timer = setTimeout(refresh, 2000);
  };
  refresh();
  return () => {
    stopped = true;
    clearTimeout(timer);
  };
}
