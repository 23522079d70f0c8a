// SPDX-License-Identifier: MIT
// The new-job form: upload a mesh file, pick s and t by clicking on the surface (or type the
// vertex ids), choose the energy and DE sizes, submit, then follow the job's page.

import * as api from './api.js';
import { MeshView } from './mesh_view.js';
import { h, navigate } from './dom.js';

const FORMATS = ['obj', 'off', 'ply', 'stl'];

export function renderSubmitForm(status) {
  const fileInput = h('input', { type: 'file', id: 'mesh-file', accept: FORMATS.map((f) => `.${f}`).join(',') });
  const formatSelect = h('select', { id: 'mesh-format' }, h('option', { value: '' }, 'by extension'),
    ...FORMATS.map((f) => h('option', { value: f }, f.toUpperCase())));
  const meshInfo = h('span', { id: 'mesh-info' }, '');
  const sInput = h('input', { type: 'number', id: 'source', min: 0, step: 1, required: true });
  const tInput = h('input', { type: 'number', id: 'target', min: 0, step: 1, required: true });
  const pickS = h('input', { type: 'radio', name: 'pick', value: 's', id: 'pick-s', checked: true });
  const pickT = h('input', { type: 'radio', name: 'pick', value: 't', id: 'pick-t' });
  const energy = h('select', { id: 'energy' }, ...['geodesic', 'vector_field', 'constant_slope'].map((e) => h('option', { value: e }, e)));
  const method = h('select', { id: 'method' }, ...['de', 'fmm', 'descent'].map((m) => h('option', { value: m }, m)));
  const population = h('input', { type: 'number', id: 'population', value: 24, min: 4 });
  const generations = h('input', { type: 'number', id: 'generations', value: 200, min: 1 });
  const seed = h('input', { type: 'number', id: 'seed', value: 1, min: 0 });
  const submit = h('button', { type: 'submit', id: 'submit', disabled: true }, 'Submit job');
  const viewEl = h('div', { id: 'pick-view', class: 'view', hidden: true });
  let meshId = null;
  let view = null;

  const updateMarkers = () => {
    if (!view) return;
    view.setMarker('s', sInput.value === '' ? null : Number(sInput.value));
    view.setMarker('t', tInput.value === '' ? null : Number(tInput.value));
  };
  sInput.addEventListener('input', updateMarkers);
  tInput.addEventListener('input', updateMarkers);

  fileInput.addEventListener('change', async () => {
    const file = fileInput.files[0];
    if (!file) return;
    const format = formatSelect.value || file.name.split('.').pop().toLowerCase();
    if (!FORMATS.includes(format)) {
      status(`Unknown mesh format "${format}": choose one of ${FORMATS.join(', ')}`, true);
      return;
    }
    status(`Uploading ${file.name}…`);
    try {
      const uploaded = await api.uploadMesh(await file.arrayBuffer(), format);
      meshId = uploaded.mesh_id;
      meshInfo.textContent = `${uploaded.vertices} vertices, ${uploaded.faces} faces`;
      meshInfo.dataset.meshId = meshId;
      const geometry = await api.getGeometry(meshId);
      viewEl.hidden = false;
      if (!view) {
        view = new MeshView(viewEl, { height: 420 });
        view.onPick = (v) => {
          const target = pickS.checked ? sInput : tInput;
          target.value = String(v);
          if (pickS.checked) pickT.checked = true;  // next click picks t
          updateMarkers();
          submit.disabled = !(meshId && sInput.value !== '' && tInput.value !== '');
        };
        window.__depath = { ...(window.__depath || {}), pickView: view };
      }
      view.setGeometry(geometry.vertices, geometry.faces);
      updateMarkers();
      status(`Uploaded ${file.name}: click the surface to pick the source, then the target.`);
      submit.disabled = !(sInput.value !== '' && tInput.value !== '');
    } catch (e) {
      status(`Upload failed: ${e.message}`, true, e.status === 401);
    }
  });

  const form = h('form', { id: 'submit-form', class: 'submit-form' },
    h('h2', {}, 'New job'),
    h('p', {}, h('label', {}, 'Mesh ', fileInput), ' ', h('label', {}, 'format ', formatSelect), ' ', meshInfo),
    viewEl,
    h('p', {}, 'Clicks pick: ', h('label', {}, pickS, ' source'), ' ', h('label', {}, pickT, ' target'), ' — ',
      h('label', {}, 's ', sInput), ' ', h('label', {}, 't ', tInput)),
    h('p', {}, h('label', {}, 'energy ', energy), ' ', h('label', {}, 'method ', method), ' ',
      h('label', {}, 'population ', population), ' ', h('label', {}, 'generations ', generations), ' ',
      h('label', {}, 'seed ', seed)),
    h('p', {}, submit),
  );
  const refresh = () => { submit.disabled = !(meshId && sInput.value !== '' && tInput.value !== ''); };
  sInput.addEventListener('input', refresh);
  tInput.addEventListener('input', refresh);
  form.addEventListener('submit', async (e) => {
    e.preventDefault();
    const spec = {
      mesh_id: meshId,
      source: Number(sInput.value),
      target: Number(tInput.value),
      energy: energy.value,
      method: method.value,
      population: Number(population.value),
      generations: Number(generations.value),
      seed: Number(seed.value),
    };
    try {
      const { id } = await api.submitJob(spec);
      navigate(`/jobs/${encodeURIComponent(id)}`);
    } catch (err) {
      status(`Submit failed: ${err.message}`, true, err.status === 401);
    }
  });
  return form;
}
