// Validates xAPI statements (JSON lines, as dentsim's outbox holds them) with an independent validator: prints one line per problem and exits 1 if any.
//
// Usage: node validate_statements.js OUTBOX.jsonl. Exit 3 when the validator module is missing,
// so that the test can skip with a clear reason rather than fail.
'use strict';
const fs = require('fs');
const path = require('path');

let validate;
try {
  validate = require(path.join(__dirname, 'node_modules', 'xapi-validation')).default;
} catch (e) {
  console.log('xapi-validation is not installed in tests/xapi (scripts/install-deps.sh runs npm ci there)');
  process.exit(3);
}

const lines = fs.readFileSync(process.argv[2], 'utf8').split('\n').filter((l) => l.length > 0);
let problems = 0;
lines.forEach((line, i) => {
  const warnings = validate(JSON.parse(line));
  for (const w of warnings) {
    problems += 1;
    console.log(`line ${i + 1}: ${w.path.join('.')}: ${w.constructor.name} ${JSON.stringify(w.data)}`);
  }
});
console.log(`${lines.length} statements, ${problems} problems`);
process.exit(problems === 0 ? 0 : 1);
