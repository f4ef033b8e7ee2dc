/**
 * The emulated clients of the paper bench (profiles.json names them):
 * browser flags (a separate browser per flag set), Playwright context
 * options (viewport, device pixel ratio, touch, user agent), the viewer's
 * box in CSS px, and a CDP CPU throttling rate (main thread only: workers
 * and SwiftShader's GL threads run at full speed, as Chromium does it).
 */
const desktop = (size) => ({ viewport: { width: size + 64, height: size + 64 } });

export const CLIENTS = {
  desktop: { args: [], size: 512, cpuRate: 0, context: desktop, what: 'desktop, WebGL2 (SwiftShader), 512² viewer' },
  noWebgl: { args: ['--disable-webgl'], size: 512, cpuRate: 0, context: desktop, what: 'desktop launched with --disable-webgl (no WebGL at all)' },
  phone: {
    args: [],
    size: 360,
    cpuRate: 0,
    context: () => ({
      viewport: { width: 390, height: 844 },
      deviceScaleFactor: 3,
      isMobile: true,
      hasTouch: true,
      userAgent: 'Mozilla/5.0 (Linux; Android 14; Pixel 8) AppleWebKit/537.36 (KHTML, like Gecko) Chrome/156.0.0.0 Mobile Safari/537.36',
    }),
    what: 'phone: 390×844 CSS px at DPR 3, touch, mobile UA, 360² viewer',
  },
  cpu6: { args: [], size: 512, cpuRate: 6, context: desktop, what: 'desktop with the main thread throttled ×6 (CDP Emulation.setCPUThrottlingRate)' },
};
