#!/usr/bin/env python3
"""A stand-in LRS for the learning-record tests: records every request and answers as an LRS would.

No real LRS runs here (the ones packaged need a database server), so the tests talk to this one.
It listens on a free localhost port, writes that port to --port-file once it accepts connections,
and appends each request to --log as one JSON line: method, path, headers, body. POST
<prefix>/statements answers 200 with the id, or 409 when that id came before (as an LRS does);
--refuse answers every request 503, an LRS that is up but will not take statements. --slow-after N
answers the first N POSTs at once and then waits --delay seconds before each answer, a slow LRS
(the request is logged when it arrives, before the wait). GET answers 405, or --get-status with
--get-body: an LRS whose answer to a query is not JSON, which the real one never sends.
"""
import argparse
import json
import os
import sys
import time
from http.server import BaseHTTPRequestHandler, HTTPServer


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--port-file", required=True)
    parser.add_argument("--log", required=True)
    parser.add_argument("--refuse", action="store_true")
    parser.add_argument("--slow-after", type=int, default=-1)
    parser.add_argument("--delay", type=float, default=0.0)
    parser.add_argument("--get-status", type=int, default=405)
    parser.add_argument("--get-body", default="")
    args = parser.parse_args()
    seen = set()
    posts = [0]

    class Handler(BaseHTTPRequestHandler):
        def log_message(self, *unused):  # keep the test's output clean
            pass

        def answer(self, status, body=b""):
            self.send_response(status)
            self.send_header("Content-Length", str(len(body)))
            self.send_header("Content-Type", "application/json")
            self.end_headers()
            self.wfile.write(body)

        def record(self, body):
            entry = {"method": self.command, "path": self.path,
                     "headers": {k.lower(): v for k, v in self.headers.items()},
                     "body": body.decode("utf-8", "replace")}
            with open(args.log, "a", encoding="utf-8") as log:
                log.write(json.dumps(entry) + "\n")

        def do_POST(self):
            body = self.rfile.read(int(self.headers.get("Content-Length", "0")))
            self.record(body)
            posts[0] += 1
            if 0 <= args.slow_after < posts[0]:
                time.sleep(args.delay)
            if args.refuse:
                return self.answer(503)
            if not self.path.split("?")[0].endswith("/statements"):
                return self.answer(404)
            try:
                statement_id = json.loads(body)["id"]
            except (ValueError, KeyError, TypeError):
                return self.answer(400)
            if statement_id in seen:
                return self.answer(409)
            seen.add(statement_id)
            self.answer(200, json.dumps([statement_id]).encode())

        def do_GET(self):
            self.record(b"")
            self.answer(args.get_status, args.get_body.encode())

    server = HTTPServer(("127.0.0.1", 0), Handler)
    # The port appears whole or not at all: written to a temporary name, then renamed.
    tmp = args.port_file + ".tmp"
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(str(server.server_address[1]))
    os.replace(tmp, args.port_file)
    server.serve_forever()


if __name__ == "__main__":
    sys.exit(main())
