// Reads every statement an LRS holds, following "more" page by page, and prints them as one JSON array: the tests' own reader, independent of dentsim's.
//
// Usage: node read_statements.js ENDPOINT USERNAME PASSWORD [LIMIT]; ENDPOINT as dentsim is given it
// ("http://127.0.0.1:PORT/xAPI"). Exit 1, with the answer printed, when a request is refused.
'use strict';
const http = require('http');

const [endpoint, username, password, limit] = process.argv.slice(2);
const base = new URL(endpoint);
const auth = 'Basic ' + Buffer.from(username + ':' + password, 'utf8').toString('base64');

function get(pathAndQuery) {
  return new Promise((resolve, reject) => {
    const req = http.get(
      { host: base.hostname, port: base.port, path: pathAndQuery, headers: { Authorization: auth, 'X-Experience-API-Version': '1.0.3' } },
      (res) => {
        let body = '';
        res.setEncoding('utf8');
        res.on('data', (chunk) => (body += chunk));
        res.on('end', () => (res.statusCode === 200 ? resolve(JSON.parse(body)) : reject(new Error(res.statusCode + ' ' + body))));
      }
    );
    req.on('error', reject);
  });
}

(async () => {
  const statements = [];
  let next = base.pathname.replace(/\/$/, '') + '/statements?ascending=true' + (limit ? '&limit=' + limit : '');
  while (next) {
    const page = await get(next);
    statements.push(...page.statements);
    next = page.more;
  }
  process.stdout.write(JSON.stringify(statements) + '\n');
})().catch((e) => {
  console.log(String(e));
  process.exit(1);
});
