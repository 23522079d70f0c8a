// SPDX-License-Identifier: MIT
// The live convergence chart (uPlot): best and mean energy per generation. Points arrive one
// progress event at a time; a redraw is coalesced to one per animation frame. The number of
// points drawn is kept in the container's data-points attribute (tests and users can read it).

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

  /// Adds (or replaces, if resent after a reconnect) the point of one generation.
  add(generation, best, mean) {
    const n = this.generations.length;
    if (n && generation <= this.generations[n - 1]) {
      const i = this.generations.indexOf(generation);
      if (i < 0) return;
      this.best[i] = best;
      this.mean[i] = mean;
    } else {
      this.generations.push(generation);
      this.best.push(best);
      this.mean.push(mean);
    }
    this.schedule();
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
