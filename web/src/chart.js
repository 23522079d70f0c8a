// SPDX-License-Identifier: MIT
// The live convergence chart (uPlot): best and mean energy per generation. Points come from
// the job's stored history (GET /v1/jobs/{id}/progress) and one progress event at a time; a
// redraw is coalesced to one per animation frame. The number of points drawn is kept in the
// container's data-points attribute (tests and users can read it).

import uPlot from 'uplot';
import 'uplot/dist/uPlot.min.css';

export class ConvergenceChart {
  constructor(container) {
    this.container = container;
    this.generations = [];
    this.best = [];
    this.mean = [];
    this.pending = false;
    this.lastDrawAt = null;
    this.onDraw = null;
    const width = Math.max(320, container.clientWidth || 560);
    this.plot = new uPlot(
      {
        width,
        height: 260,
        scales: { x: { time: false } },
        axes: [{ label: 'generation' }, { label: 'energy', size: 70 }],
        series: [
          { label: 'generation' },
          { label: 'best', stroke: '#db1414', width: 2 },
          { label: 'mean', stroke: '#3366d9', width: 2 },
        ],
      },
      [[], [], []],
      container,
    );
    container.dataset.points = '0';
    this.resizeObserver = new ResizeObserver(() => {
      const w = Math.max(320, container.clientWidth);
      if (w !== this.plot.width) this.plot.setSize({ width: w, height: 260 });
    });
    this.resizeObserver.observe(container);
  }

  /// Adds (or replaces, if resent after a reconnect) the point of one generation; a point
  /// older than the newest (from the stored history, loaded while events arrive) goes in its
  /// place, so the series stays ordered by generation.
  add(generation, best, mean) {
    this.insert(generation, best, mean);
    this.schedule();
  }

  /// The stored history: {generation: [...], best_energy: [...], mean_energy: [...]}.
  addHistory(history) {
    const g = history.generation || [];
    for (let i = 0; i < g.length; ++i) this.insert(g[i], history.best_energy[i], history.mean_energy[i]);
    this.schedule();
  }

  insert(generation, best, mean) {
    const n = this.generations.length;
    if (!n || generation > this.generations[n - 1]) {
      this.generations.push(generation);
      this.best.push(best);
      this.mean.push(mean);
      return;
    }
    let lo = 0, hi = n;  // first index with generations[i] >= generation
    while (lo < hi) {
      const mid = (lo + hi) >> 1;
      if (this.generations[mid] < generation) lo = mid + 1;
      else hi = mid;
    }
    if (this.generations[lo] === generation) {
      this.best[lo] = best;
      this.mean[lo] = mean;
    } else {
      this.generations.splice(lo, 0, generation);
      this.best.splice(lo, 0, best);
      this.mean.splice(lo, 0, mean);
    }
  }

  schedule() {
    if (this.pending) return;
    this.pending = true;
    requestAnimationFrame(() => {
      this.pending = false;
      this.plot.setData([this.generations, this.best, this.mean]);
      this.container.dataset.points = String(this.generations.length);
      this.container.dataset.lastGeneration = String(this.generations[this.generations.length - 1] ?? '');
      this.lastDrawAt = performance.now();
      if (this.onDraw) this.onDraw(this.generations.length, this.lastDrawAt);
    });
  }
}
