// The download of a range of steps (step-export.js, POST /api/steps-zip): the export box's button
// saves <algorithm>-steps-A-B.zip, a ZIP read here from its central directory: B - A + 1 stored
// PNG files step-001.png ..., each of the picture's size (from its IHDR); a range over 200 steps
// leaves the button disabled with a note. Works in a page of its own.

import fs from 'node:fs';
import path from 'node:path';

// The entries of a ZIP's central directory: {name, method, size, offset}.
function zipEntries(bytes) {
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  let end = bytes.length - 22;
  while (end >= 0 && view.getUint32(end, true) !== 0x06054b50) end -= 1;
  if (end < 0) throw new Error('no end of central directory record');
  const count = view.getUint16(end + 10, true);
  let at = view.getUint32(end + 16, true);
  const entries = [];
  for (let k = 0; k < count; ++k) {
    if (view.getUint32(at, true) !== 0x02014b50) throw new Error(`entry ${k}: no central directory header`);
    const nameLength = view.getUint16(at + 28, true);
    const skip = nameLength + view.getUint16(at + 30, true) + view.getUint16(at + 32, true);
    entries.push({
      name: new TextDecoder().decode(bytes.subarray(at + 46, at + 46 + nameLength)),
      method: view.getUint16(at + 10, true),
      size: view.getUint32(at + 24, true),
      offset: view.getUint32(at + 42, true),
    });
    at += 46 + skip;
  }
  return entries;
}

// The width and height of the PNG stored at a local header's offset.
function pngSize(bytes, offset) {
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  if (view.getUint32(offset, true) !== 0x04034b50) throw new Error(`no local header at ${offset}`);
  const data = offset + 30 + view.getUint16(offset + 26, true) + view.getUint16(offset + 28, true);
  const signature = [...bytes.subarray(data, data + 8)].join(',');
  if (signature !== '137,80,78,71,13,10,26,10') throw new Error(`no PNG signature at ${data}`);
  return { width: view.getUint32(data + 16), height: view.getUint32(data + 20) };
}

export default async (h) => {
  const { check, assert } = h;
  const { browser, page } = await h.newBrowser({ viewport: { width: 1280, height: 800 }, acceptDownloads: true });
  // A new page's first picture waits for the server's workers, which ctest -j2 keeps busy.
  const idle = () => page.waitForFunction(() => window.hsrView && window.hsrView.idle()
    && document.querySelector('#canvas').dataset.state !== 'loading', null, { timeout: 90_000 });
  // zbuffer's first picture with its steps. Under ctest -j2 it has been seen not to come within
  // 90 s once in several runs (never alone); the page is then loaded again, once.
  const zbufferShown = async () => {
    await idle();
    if ((await page.$eval('#algorithm', (s) => s.value)) !== 'zbuffer') {
      await page.selectOption('#algorithm', 'zbuffer');
      await page.waitForFunction(() => window.hsrView.lastResponse?.steps, null, { timeout: 90_000 });
      await idle();
    }
  };
  try {
    await zbufferShown().catch(async (e) => {
      console.log(`note  export steps: ${e.message.split('\n')[0]}; loading the page again`);
      await page.reload();
      await zbufferShown();
    });

    await check('export steps: the button downloads steps 2..4 as a ZIP of three PNGs', async () => {
      await page.waitForSelector('#step-export:not([hidden])', { timeout: 30_000 });
      await page.click('#step-export summary');
      await page.fill('#step-export-from', '2');
      await page.fill('#step-export-to', '4');
      const [download] = await Promise.all([
        page.waitForEvent('download', { timeout: 60_000 }),
        page.click('#step-export-zip'),
      ]);
      assert(download.suggestedFilename() === 'zbuffer-steps-2-4.zip', `saved as ${download.suggestedFilename()}`);
      const saved = path.join(h.scratch, 'steps.zip');
      await download.saveAs(saved);
      const bytes = new Uint8Array(fs.readFileSync(saved));
      const entries = zipEntries(bytes);
      assert(entries.map((e) => e.name).join(' ') === 'step-001.png step-002.png step-003.png',
        `entries: ${entries.map((e) => e.name).join(' ')}`);
      const { width, height } = await page.evaluate(() => window.hsrView.lastResponse);
      for (const e of entries) {
        assert(e.method === 0 && e.size > 60, `${e.name}: method ${e.method}, ${e.size} bytes`);
        const size = pngSize(bytes, e.offset);
        assert(size.width === width && size.height === height, `${e.name} is ${size.width}×${size.height}, the picture ${width}×${height}`);
      }
      assert(bytes.length > entries.reduce((sum, e) => sum + e.size, 0), `${bytes.length} bytes in all`);
      await page.waitForFunction(() => /zbuffer-steps-2-4\.zip/.test(document.querySelector('#step-export-note').textContent));
    });

    await check('export steps: over 200 steps the download is disabled, with a note', async () => {
      await page.fill('#step-export-from', '1');
      await page.fill('#step-export-to', '201');
      assert(await page.$eval('#step-export-zip', (b) => b.disabled), 'the download is enabled for 201 steps');
      assert(!(await page.$eval('#step-export-copy', (b) => b.disabled)), 'the command is disabled for 201 steps');
      const note = await page.$eval('#step-export-note', (e) => e.textContent);
      assert(/at most 200 steps/.test(note), `note: ${note}`);
    });
  } finally {
    await browser.close();
  }
};
