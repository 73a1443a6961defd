#!/usr/bin/env node
// Lint the project's Cypher templates with Neo4j's own linter
// (lintCypherQuery of @neo4j-cypher/language-support, the engine behind the Neo4j VS Code
// extension: the Cypher 5 parser plus Neo4j's semantic analysis).
//
//   node .ci/cypher-lint/lint.mjs                 # every sg3d/cypher/*.cypher of the repo
//   node .ci/cypher-lint/lint.mjs FILE.cypher...  # just these files
//
// Output: one line per diagnostic, `FILE:LINE:COL: error|warning: MESSAGE` (1-based line and
// column), then `cypher lint: N files, E errors, W warnings`. Exit status: 0 when there is no
// error (warnings never fail), 1 when there is at least one error, 2 on a usage error or a file
// that cannot be read.
//
// What is checked, and what is deliberately not:
// - Errors (severity 1): syntax errors and semantic errors (undefined variable, wrong type,
//   Neo4j 4 syntax removed in 5, ...). These fail the check.
// - Warnings (severity 2 and lower): deprecations (e.g. `CALL { WITH x ... }` instead of
//   `CALL (x) { ... }`, `id()`), cartesian products, ... Reported, never fail.
// - "Parameter $x is not defined." is dropped: every template takes its parameters from the
//   application at run time, so no parameter is ever "defined" for the linter.
// - The dbSchema is empty on purpose. Unknown labels / relationship types / properties are only
//   reported when a schema lists the ones present in a database; ours are created by the
//   application (an empty store has none, and the model is documented in cypher/schema.cypher),
//   so a fixed list here would only duplicate the model. Procedure/function existence checks
//   likewise need a live server's registry and are skipped.
// - Full-line `//` comments are blanked (line numbers are kept) before linting, exactly as
//   sg3d/graphdb/cypher.py strips them before sending a statement. Multi-statement files
//   (cypher/schema*.cypher, statements separated by `;`) are linted as one document, as
//   cypher-shell would read them; an empty statement between two `;` is an error.
// - `REL_TYPE` in templates is an ordinary identifier, so such files lint as they are.

import { createRequire } from 'node:module';
import { existsSync, readdirSync, readFileSync } from 'node:fs';
import { dirname, join, relative, resolve, isAbsolute } from 'node:path';
import { fileURLToPath } from 'node:url';

const HERE = dirname(fileURLToPath(import.meta.url));
const REPO = resolve(HERE, '..', '..');
const CYPHER_DIR = join(REPO, 'sg3d', 'cypher');

// The package's ESM entry (2.0.0-next.20) uses extension-less relative imports, which Node's
// ESM loader rejects; its CommonJS bundle (exports["."].require) loads everywhere.
const require = createRequire(import.meta.url);
let lintCypherQuery;
try {
  ({ lintCypherQuery } = require('@neo4j-cypher/language-support'));
} catch (err) {
  console.error(
    `cypher lint: cannot load @neo4j-cypher/language-support (${err.code ?? err.message}); ` +
      'run `npm ci --prefix .ci/cypher-lint` first',
  );
  process.exit(2);
}

const SEVERITY_ERROR = 1; // vscode-languageserver-types DiagnosticSeverity.Error
const PARAM_NOT_DEFINED = /^Parameter \$.+ is not defined\.$/;

function usage() {
  console.log('usage: node .ci/cypher-lint/lint.mjs [FILE.cypher ...]');
  console.log('Lints the given files, or every sg3d/cypher/*.cypher of the repository.');
}

function displayPath(abs) {
  const rel = relative(process.cwd(), abs);
  return rel && !rel.startsWith('..') && !isAbsolute(rel) ? rel : abs;
}

/** The text sg3d/graphdb/cypher.py would send: full-line `//` comments blanked, lines kept. */
function stripLineComments(text) {
  return text
    .split('\n')
    .map((line) => (line.trimStart().startsWith('//') ? '' : line))
    .join('\n');
}

function lintText(text) {
  const query = stripLineComments(text);
  if (query.trim() === '') {
    return [
      {
        severity: SEVERITY_ERROR,
        message: 'file holds no Cypher statement',
        range: { start: { line: 0, character: 0 } },
      },
    ];
  }
  const result = lintCypherQuery(query, {});
  // 2.0.0-next.20 returns the diagnostics array; later releases return { diagnostics, ... }.
  const diagnostics = Array.isArray(result) ? result : (result?.diagnostics ?? []);
  return diagnostics
    .filter((d) => !PARAM_NOT_DEFINED.test(d.message))
    .sort(
      (a, b) =>
        a.range.start.line - b.range.start.line ||
        a.range.start.character - b.range.start.character,
    );
}

function main(argv) {
  if (argv.includes('-h') || argv.includes('--help')) {
    usage();
    return 0;
  }
  let files;
  if (argv.length > 0) {
    files = argv.map((f) => resolve(f));
  } else {
    if (!existsSync(CYPHER_DIR)) {
      console.error(`cypher lint: no directory ${displayPath(CYPHER_DIR)}`);
      return 2;
    }
    files = readdirSync(CYPHER_DIR)
      .filter((f) => f.endsWith('.cypher'))
      .sort()
      .map((f) => join(CYPHER_DIR, f));
  }

  let errors = 0;
  let warnings = 0;
  let unreadable = 0;
  for (const file of files) {
    const shown = displayPath(file);
    let text;
    try {
      text = readFileSync(file, 'utf8');
    } catch (err) {
      console.log(`${shown}: cannot read: ${err.code ?? err.message}`);
      unreadable += 1;
      continue;
    }
    let diagnostics;
    try {
      diagnostics = lintText(text);
    } catch (err) {
      // A crash of the linter on a file must not pass silently.
      diagnostics = [
        {
          severity: SEVERITY_ERROR,
          message: `linter crashed: ${err.message}`,
          range: { start: { line: 0, character: 0 } },
        },
      ];
    }
    for (const d of diagnostics) {
      // LSP: a diagnostic without severity is left to the client; count it as an error.
      const isError = d.severity === undefined || d.severity === SEVERITY_ERROR;
      if (isError) errors += 1;
      else warnings += 1;
      const { line, character } = d.range.start;
      const message = d.message.replace(/\s*\n\s*/g, ' ');
      console.log(
        `${shown}:${line + 1}:${character + 1}: ${isError ? 'error' : 'warning'}: ${message}`,
      );
    }
  }

  const plural = (n, word) => `${n} ${word}${n === 1 ? '' : 's'}`;
  console.log(
    `cypher lint: ${plural(files.length, 'file')}, ${plural(errors, 'error')}, ` +
      `${plural(warnings, 'warning')}` +
      (unreadable ? `, ${unreadable} unreadable` : ''),
  );
  if (unreadable) return 2;
  return errors > 0 ? 1 : 0;
}

process.exitCode = main(process.argv.slice(2));
