// Latest-wins requests: one in flight; while it runs, a newer job replaces the one waiting, which
// starts when the current one returns. So when the mouse stops, the last frame shown is the final
// camera, and a slow render never queues up a backlog of stale ones. A job that has run for longer
// than supersedeAfterMs is not waited for: the newer one starts at once, and the server cancels the
// older (both come from the same page).

export class LatestWins {
  // run(job, isStale) performs one job (a promise); isStale() tells it a newer job took over, so that
  // it shows nothing. onBusy(busy) hears when work starts and ends.
  constructor(run, onBusy, supersedeAfterMs = 500) {
    this.run = run;
    this.onBusy = onBusy;
    this.supersedeAfterMs = supersedeAfterMs;
    this.inFlight = false;
    this.pending = null;
    this.generation = 0;
    this.startedAt = 0;
  }

  submit(job) {
    if (this.inFlight && performance.now() - this.startedAt < this.supersedeAfterMs) {
      this.pending = job;
      return;
    }
    this.pending = null;
    this.start(job);
  }

  async start(job) {
    const generation = ++this.generation;
    this.inFlight = true;
    this.startedAt = performance.now();
    this.onBusy(true);
    try {
      await this.run(job, () => generation !== this.generation);
    } catch (e) {
      console.error(e);
    }
    if (generation !== this.generation) return;  // a newer job carries on
    const next = this.pending;
    this.pending = null;
    if (next) {
      this.start(next);
    } else {
      this.inFlight = false;
      this.onBusy(false);
    }
  }

  // Milliseconds the job in flight has run, or null.
  running() {
    return this.inFlight ? performance.now() - this.startedAt : null;
  }

  idle() {
    return !this.inFlight && this.pending === null;
  }
}
