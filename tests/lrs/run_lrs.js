// Starts the test LRS (xapi-statements, Learning Locker's statement service) on a given port, in memory, with the credentials it must be given.
//
// Usage: node run_lrs.js PORT USERNAME PASSWORD WATCH_PID READY_FILE, run in a scratch folder (the
// service writes its access log under ./storage/accessLogs, one line per request). READY_FILE
// appears once GET /xAPI/about answers. Exit 3 when the package is missing, so that a test can skip
// with a clear reason.
//
// Why a wrapper: with AUTH_REPO=test the service takes any request, with or without credentials.
// With AUTH_REPO=fetch it asks a client-info endpoint who the request's Authorization header belongs
// to, as it asks Learning Locker's main app in a school's deployment. This script is that endpoint:
// it knows one client, USERNAME with PASSWORD, whose authority the LRS stamps on every statement it
// stores; any other header (none, a wrong password) is no client, and the LRS refuses the request.
// So a stored statement whose authority names USERNAME proves the credentials reached the LRS.
// The script exits when WATCH_PID is gone, so that a test that dies never leaves an LRS running.
'use strict';
const http = require('http');
const path = require('path');

const fs = require('fs');

const [port, username, password, watchPid, readyFile] = process.argv.slice(2);
if (!port || username === undefined || password === undefined || !watchPid || !readyFile) {
  console.error('usage: node run_lrs.js PORT USERNAME PASSWORD WATCH_PID READY_FILE');
  process.exit(2);
}
const serverJs = path.join(__dirname, 'node_modules', 'xapi-statements', 'dist', 'server.js');
try {
  require.resolve(serverJs);
} catch (e) {
  console.log('xapi-statements is not installed in tests/lrs (scripts/install-deps.sh runs npm ci there)');
  process.exit(3);
}

const expected = 'Basic ' + Buffer.from(username + ':' + password, 'utf8').toString('base64');
const client = {
  _id: '5f0000000000000000000001',
  title: 'dentsim test client',
  authority: { objectType: 'Agent', account: { homePage: 'https://lrs.test.invalid', name: username } },
  isTrusted: true,
  lrs_id: '5f0000000000000000000002',
  organisation: '5f0000000000000000000003',
  scopes: ['all'],
};

// The client-info endpoint: 200 and the client for the right header, 404 (no such client) otherwise.
const clientInfo = http.createServer((req, res) => {
  const known = req.headers.authorization === expected;
  res.writeHead(known ? 200 : 404, { 'Content-Type': 'application/json' });
  res.end(known ? JSON.stringify(client) : '{}');
});

clientInfo.listen(0, '127.0.0.1', () => {
  Object.assign(process.env, {
    AUTH_REPO: 'fetch',
    LL_CLIENT_INFO_ENDPOINT: 'http://127.0.0.1:' + clientInfo.address().port + '/client',
    EVENTS_REPO: 'test',
    MODELS_REPO: 'memory',
    STORAGE_REPO: 'memory',
    EXPRESS_PORT: port,
    WINSTON_CONSOLE_LEVEL: 'error',
  });
  require(serverJs);
  // Ready when it answers: asked again every 100 ms until it does.
  const poll = () => {
    http
      .get({ host: '127.0.0.1', port: Number(port), path: '/xAPI/about' }, (res) => {
        res.resume();
        if (res.statusCode === 200) fs.writeFileSync(readyFile, port);
        else setTimeout(poll, 100);
      })
      .on('error', () => setTimeout(poll, 100));
  };
  poll();
  // Gone with the process that started it, however that process ended.
  setInterval(() => {
    try {
      process.kill(Number(watchPid), 0);
    } catch (e) {
      process.exit(0);
    }
  }, 500).unref();
});
