// Latest-wins requests: at most one in flight; while it runs, a newer job replaces the one waiting,
// which starts when the current one returns. So when the mouse stops, the last frame shown is the
// final camera, and a slow render never queues up a backlog of stale ones.

export class LatestWins {
  // run(job) performs one job (a promise); onBusy(busy) hears when work starts and ends.
  constructor(run, onBusy) {
    this.run = run;
    this.onBusy = onBusy;
    this.inFlight = false;
    this.pending = null;
  }

  submit(job) {
    if (this.inFlight) {
      this.pending = job;
      return;
    }
    this.start(job);
  }

  async start(job) {
    this.inFlight = true;
    this.onBusy(true);
    try {
      await this.run(job);
    } catch (e) {
      console.error(e);
    }
    const next = this.pending;
    this.pending = null;
    if (next) {
      this.start(next);
    } else {
      this.inFlight = false;
      this.onBusy(false);
    }
  }

  idle() {
    return !this.inFlight && this.pending === null;
  }
}
