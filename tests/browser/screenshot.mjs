// screenshot.mjs - a picture of the web viewer for the README (docs/images/viewer.png),
// taken with the same headless Chromium and playwright-core as the browser test, from a
// refractd that is already running (deploy/demo.sh starts one with the example scenes):
//
//   node tests/browser/screenshot.mjs http://127.0.0.1:8750 wine_glass docs/images/viewer.png
//
// It waits until the view shows a full frame with its irradiance ready (the light
// simulation of a lit scene takes a while on llvmpipe), then saves the whole page.
import { chromium } from 'playwright-core';

const [url = 'http://127.0.0.1:8750', scene = 'wine_glass', out = 'viewer.png'] = process.argv.slice(2);
const viewport = { width: 1200, height: 700 };

const browser = await chromium.launch({ executablePath: process.env.REFRACT_CHROMIUM || '/usr/bin/chromium',
                                        args: ['--no-sandbox', '--disable-dev-shm-usage'] });
try {
  const page = await browser.newPage({ viewport, deviceScaleFactor: 1 });
  await page.goto(`${url}/viewer/${scene}`);
  await page.waitForFunction(() => {
    const v = window.refractViewer;
    const f = v && v.status && v.status.frame;
    return f && v.shown && v.shown.seq === f.seq && v.status.state === 'idle' && f.kind === 'full' &&
           (f.irradiance === 'ready' || f.irradiance === 'not-needed');
  }, null, { timeout: 600000, polling: 500 });
  await page.waitForTimeout(1500); // one more status poll, so the status line is current
  await page.screenshot({ path: out });
  console.log(`saved ${out}`);
} finally {
  await browser.close();
}
