// SPDX-License-Identifier: MIT
// The page of one job (/jobs/{id}): id and state, live progress, the convergence chart, the
// 3D view with the best path so far and the s/t markers, the result's figures and downloads.
// Live updates come from the job's event stream (progress, path, state, result); the chart
// also loads the job's stored per-generation history (GET /v1/jobs/{id}/progress) once the
// stream is connected, so a finished job shows its whole convergence and a running one the
// generations before the page was opened. A vector-field job's field is an overlay that a
// checkbox turns on and off.

import * as api from './api.js';
import { followEvents } from './sse.js';
import { ConvergenceChart } from './chart.js';
import { MeshView } from './mesh_view.js';
import { h, formatNumber, navigate } from './dom.js';

const TERMINAL = new Set(['succeeded', 'failed', 'cancelled']);

export function renderJobPage(root, jobId, status) {
  const stateEl = h('span', { id: 'job-state', class: 'state' }, '…');
  const progressEl = h('span', { id: 'job-progress' }, '');
  const chartEl = h('div', { id: 'chart', class: 'chart' });
  const viewEl = h('div', { id: 'view', class: 'view' });
  const fieldToggle = h('input', { type: 'checkbox', id: 'field-toggle', checked: true });
  const fieldNote = h('span', { id: 'field-note', class: 'note' }, '');
  const fieldControl = h('label', { id: 'field-control', class: 'overlay-toggle', hidden: true },
    fieldToggle, ' show the field', ' ', fieldNote);
  const figuresEl = h('table', { id: 'figures', class: 'figures' });
  const downloadsEl = h('p', { id: 'downloads', class: 'downloads' });
  const cancelButton = h('button', { id: 'cancel', type: 'button', hidden: true }, 'Cancel job');
  root.replaceChildren(
    h('p', {}, h('a', { href: '/', onclick: (e) => { e.preventDefault(); navigate('/'); } }, '← all jobs')),
    h('h1', {}, 'Job ', h('code', { id: 'job-id' }, jobId)),
    h('p', { class: 'status-line' }, 'State: ', stateEl, ' ', progressEl, ' ', cancelButton),
    h('div', { class: 'panels' },
      h('section', { class: 'panel' }, h('h2', {}, 'Surface and path'), viewEl, fieldControl),
      h('section', { class: 'panel' }, h('h2', {}, 'Convergence'), chartEl, h('h2', {}, 'Result'), figuresEl, downloadsEl)),
  );

  const chart = new ConvergenceChart(chartEl);
  const view = new MeshView(viewEl);
  // Latencies (ms) of the chart: from receiving a progress event, and from the server logging
  // it (its `time`, same clock when the browser runs on the server's machine).
  const live = { jobId, progressEvents: 0, pathEvents: 0, lastProgressReceivedAt: null, lastProgressTime: null,
    latencies: [], serverToChart: [] };
  window.__depath = { ...(window.__depath || {}), job: live, view, chart };
  chart.onDraw = (n, at) => {
    if (live.lastProgressReceivedAt !== null) live.latencies.push(at - live.lastProgressReceivedAt);
    if (live.lastProgressTime) live.serverToChart.push(Date.now() - live.lastProgressTime * 1000);
    live.lastProgressReceivedAt = null;
    live.lastProgressTime = null;
  };
  let spec = null;
  let stop = null;
  let historyRequested = false;
  const loadHistory = () => {
    if (historyRequested) return;
    historyRequested = true;
    api.getProgress(jobId).then((history) => {
      live.historyPoints = history.generation.length;
      chart.addHistory(history);
    }, (e) => status(`Cannot load the convergence history: ${e.message}`, true));
  };

  // The field overlay (vector-field jobs): loaded when first shown, then kept.
  let field = null;
  const showField = async () => {
    viewEl.dataset.fieldShown = String(fieldToggle.checked);
    if (!fieldToggle.checked) return view.setField(null);
    try {
      if (!field) field = (await api.getField(jobId)).field;
      if (fieldToggle.checked) view.setField(field);
      fieldNote.textContent = '';
    } catch (e) {
      fieldNote.textContent = `(${e.message})`;
      fieldToggle.checked = false;
      fieldToggle.disabled = true;
      viewEl.dataset.fieldShown = 'false';
    }
  };
  fieldToggle.addEventListener('change', showField);
  let finished = false;

  const setState = (state) => {
    stateEl.textContent = state;
    stateEl.className = `state state-${state}`;
    root.dataset.state = state;
    cancelButton.hidden = TERMINAL.has(state);
    finished = TERMINAL.has(state);
  };
  const showProgress = (p) => {
    if (!p) return;
    const total = p.generations ?? p.max_generations;
    progressEl.textContent = `generation ${p.generation}${total ? ` / ${total}` : ''}, best ${formatNumber(p.best_energy)}`;
  };
  let resultShown = false;
  const showResult = (result) => {
    if (!result) return;
    resultShown = true;
    root.dataset.result = 'shown';
    view.setPath(result.points, { final: true });
    const rows = [
      ['energy', result.energy], ['length', result.length], ['fmm energy', result.fmm_energy],
      ['generations', result.generations], ['evaluations', result.evaluations],
      ['seconds', result.elapsed_seconds ?? result.seconds], ['path points', result.points ? result.points.length : null],
    ].filter(([, v]) => v !== undefined && v !== null);
    figuresEl.replaceChildren(...rows.map(([k, v]) => h('tr', {}, h('th', {}, k), h('td', {}, formatNumber(v, 8)))));
    downloadsEl.replaceChildren('Download: ',
      ...['json', 'obj', 'ply', 'csv'].flatMap((f, i) => [i ? ' · ' : '',
        h('a', { href: api.resultUrl(jobId, f), download: `${jobId}.${f}`, class: 'download' }, f.toUpperCase())]));
  };
  const showError = (err) => {
    if (!err) return;
    figuresEl.replaceChildren(h('tr', {}, h('th', {}, 'error'), h('td', { class: 'error' }, `${err.code || ''} ${err.message || err}`)));
  };

  cancelButton.addEventListener('click', async () => {
    try {
      await api.cancelJob(jobId);
    } catch (e) {
      status(e.message, true);
    }
  });

  const onEvent = (ev) => {
    // Connected: from now on every progress event reaches the chart, the history has the rest.
    loadHistory();
    const d = ev.data || {};
    if (ev.event === 'progress' || ev.event === 'path') {
      // A path event is a progress event that also carries the best path so far.
      live.progressEvents++;
      live.lastProgressReceivedAt = ev.receivedAt;
      live.lastProgressTime = typeof d.time === 'number' ? d.time : null;
      chart.add(d.generation, d.best_energy, d.mean_energy);
      showProgress({ ...d, generations: d.generations || spec?.generations });
      const points = d.path ? d.path.points : d.points;
      if (ev.event === 'path' && points && !finished) {
        live.pathEvents++;
        view.setPath(points);
      }
    } else if (ev.event === 'state') {
      setState(d.state);
      if (d.error) showError(d.error);
      // The stream stops at a final state; the result may not have been in it yet.
      if (d.state === 'succeeded' && !resultShown) api.getJob(jobId).then((j) => showResult(j.result), () => {});
    } else if (ev.event === 'result') {
      showResult(d.result || d);
    }
  };

  (async () => {
    let job;
    try {
      job = await api.getJob(jobId);
    } catch (e) {
      setState('unknown');
      status(`Cannot load job ${jobId}: ${e.message}`, true, e.status === 401);
      return;
    }
    spec = job.spec || {};
    setState(job.state);
    showProgress(job.progress);
    showError(job.error);
    if (job.result) showResult(job.result);
    try {
      live.timing = { jobLoaded: performance.now() };
      const geometry = await api.getGeometry(spec.mesh_id);
      live.timing.geometryLoaded = performance.now();
      view.setGeometry(geometry.vertices, geometry.faces);
      live.timing.geometryBuilt = performance.now();
      view.setMarker('s', spec.source);
      view.setMarker('t', spec.target);
      view.lookAtVertices([spec.source, spec.target]);
      if (spec.energy === 'vector_field') {
        fieldControl.hidden = false;
        await showField();
      }
      if (job.result) view.setPath(job.result.points, { final: true });
    } catch (e) {
      status(`Cannot load the mesh: ${e.message}`, true);
    }
    stop = followEvents(`/v1/jobs/${encodeURIComponent(jobId)}/events`, {
      onEvent,
      onError: (e) => status(`Event stream: ${e.message}`, true, e.status === 401),
      isFinal: (ev) => ev.event === 'state' && TERMINAL.has(ev.data && ev.data.state),
    });
  })();

  return () => {
    if (stop) stop();
  };
}
