// The docs' math offline: runs the KaTeX loader of docs/katex-header.html, as a doc page's
// header, against a stand-in for the browser in which the CDN cannot be reached. It must fall
// back to the copy beside the docs (scripts/offline-katex), ask only for files that exist
// there relative to the page, and render the page once they have loaded.
// Usage: node scripts/check-katex.js DOC_PAGE.html (a page of target/doc).
"use strict";
const fs = require("fs");
const path = require("path");
const page = process.argv[2];
const html = fs.readFileSync(page, "utf8");
const root = /<meta name="rustdoc-vars" data-root-path="([^"]*)"/.exec(html)[1];
const script = /<script>\s*(\(function \(\) \{[\s\S]*?\}\)\(\);)\s*<\/script>/.exec(html)[1];
const asked = [];
let rendered = 0;
const head = {
  appendChild(e) {
    const url = e.src || e.href;
    asked.push(url);
    const offline = url.startsWith("https://");
    const file = path.resolve(path.dirname(page), url);
    const ok = !offline && fs.existsSync(file);
    if (e.src && e.src.endsWith("auto-render.min.js") && ok) {
      global.renderMathInElement = (body, options) => {
        if (body !== document.body || options.delimiters.length !== 3) throw new Error("bad call");
        rendered += 1;
      };
    }
    const done = ok ? e.onload : e.onerror;
    if (done) setImmediate(done);
  },
};
global.document = {
  head,
  body: {},
  readyState: "complete",
  querySelector: (q) => (q === 'meta[name="rustdoc-vars"]'
    ? { getAttribute: (a) => (a === "data-root-path" ? root : null) } : null),
  createElement: (tag) => ({ tag }),
  addEventListener: () => { throw new Error("the page is loaded"); },
};
eval(script);
setTimeout(() => {
  const local = asked.filter((u) => !u.startsWith("https://"));
  const missing = local.filter((u) => !fs.existsSync(path.resolve(path.dirname(page), u)));
  if (rendered !== 1 || local.length !== 3 || missing.length > 0) {
    console.error(`check-katex: ${page}: rendered ${rendered} time(s); local files ${local}; missing ${missing}`);
    process.exit(1);
  }
  console.log(`docs' math offline: ${page} renders from ${local[0].replace(/katex.min.css$/, "")}`);
}, 200);
