"""The studio's local web server: a thin HTTP layer over :mod:`machdyn.studio`'s calls.

Tornado serves the page (``static/``) and a small JSON API; every answer is a
call of the public Python API (reading the document, solving, drawing,
exporting, synthesising) made in a worker thread, so a long synthesis never
stalls a drag.

Security, for a server any page in the user's browser could try to reach:

* it binds to 127.0.0.1 only;
* a request whose ``Host`` is not the studio's own (``127.0.0.1:PORT`` or
  ``localhost:PORT``) is refused (DNS rebinding), and so is one whose
  ``Origin`` (or ``Sec-Fetch-Site``) says it comes from another site;
* API calls are ``POST`` with ``Content-Type: application/json`` (a form on
  another site cannot send that without a preflight, which is never granted),
  bodies over :data:`BODY_LIMIT` get 413 (read and dropped, never kept; over
  16 times that the connection is refused), malformed
  JSON 400, a document the library refuses 422 naming the key, and any other
  exception 500 with a message for the page and a traceback in the log;
* no request names a file: the page reads files the user picks in the browser
  and sends their text; the server writes only the one file given on the
  command line;
* the page has a strict Content-Security-Policy (no inline script, nothing
  from the network) and puts user text into the page as text only.
"""

from __future__ import annotations

import asyncio
import json
import logging
import threading
import time
import traceback
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

import tornado.httpserver
import tornado.ioloop
import tornado.web

from ..errors import MachdynError

__all__ = ["BODY_LIMIT", "Studio"]

#: Largest request body accepted, bytes (a drawn document is a few kB; a CSV of
#: path points or a dropped machine file stays far below this).
BODY_LIMIT = 2_000_000

STATIC = Path(__file__).with_name("static")
log = logging.getLogger("machdyn.studio")

CSP = (
    "default-src 'self'; script-src 'self'; style-src 'self'; img-src 'self' data: blob:; "
    "connect-src 'self'; object-src 'none'; base-uri 'none'; form-action 'none'; "
    "frame-ancestors 'none'"
)


class Refused(Exception):
    """A request answered with a 4xx status and a message for the page."""

    def __init__(self, status: int, message: str) -> None:
        super().__init__(message)
        self.status = status
        self.message = message


def _allowed_hosts(port: int) -> set[str]:
    return {f"127.0.0.1:{port}", f"localhost:{port}"}


class _Guarded(tornado.web.RequestHandler):
    """Host, Origin and fetch-site checks, and security headers, on every request."""

    def set_default_headers(self) -> None:
        self.set_header("X-Content-Type-Options", "nosniff")
        self.set_header("Referrer-Policy", "no-referrer")
        self.set_header("Cache-Control", "no-store")
        self.set_header("Cross-Origin-Resource-Policy", "same-origin")

    def _guard(self) -> None:
        port = self.settings["studio"].port
        host = self.request.headers.get("Host", "")
        if host not in _allowed_hosts(port):
            raise Refused(403, f"refused: the Host {host!r} is not this studio's")
        origin = self.request.headers.get("Origin")
        if origin is not None and origin not in {f"http://{h}" for h in _allowed_hosts(port)}:
            raise Refused(403, f"refused: requests from {origin!r} are not allowed")
        site = self.request.headers.get("Sec-Fetch-Site")
        if site is not None and site not in ("same-origin", "none"):
            raise Refused(403, f"refused: a {site} request")

    def prepare(self) -> None:
        try:
            self._guard()
        except Refused as r:
            self._refuse(r)

    def _refuse(self, r: Refused) -> None:
        self.set_status(r.status)
        self.set_header("Content-Type", "application/json; charset=utf-8")
        self.finish(json.dumps({"error": r.message}))

    def write_error(self, status_code: int, **kwargs: Any) -> None:
        self.set_header("Content-Type", "application/json; charset=utf-8")
        self.finish(json.dumps({"error": self._reason or f"HTTP {status_code}"}))


class PageHandler(_Guarded):
    """``GET /``: the single page."""

    def get(self) -> None:
        if self._finished:
            return
        self.set_header("Content-Security-Policy", CSP)
        self.set_header("Content-Type", "text/html; charset=utf-8")
        self.finish((STATIC / "index.html").read_bytes())


class StaticHandler(tornado.web.StaticFileHandler):
    """The page's modules, style sheet and icons, behind the same checks."""

    def prepare(self) -> None:
        try:
            _Guarded._guard(self)  # type: ignore[arg-type]
        except Refused as r:
            self.set_status(r.status)
            self.finish(json.dumps({"error": r.message}))

    def set_extra_headers(self, path: str) -> None:
        self.set_header("X-Content-Type-Options", "nosniff")
        self.set_header("Cache-Control", "no-store")

    def write_error(self, status_code: int, **kwargs: Any) -> None:
        self.finish(json.dumps({"error": f"HTTP {status_code}"}))


@tornado.web.stream_request_body
class ApiHandler(_Guarded):
    """``POST /api/<call>`` with a JSON body; the answer is JSON (or a file to download)."""

    def prepare(self) -> None:
        super().prepare()
        if self._finished:
            return
        self._chunks: list[bytes] = []
        self._size = 0
        try:
            if self.request.method != "POST":
                raise Refused(405, "use POST")
            kind = self.request.headers.get("Content-Type", "").split(";")[0].strip().lower()
            if kind != "application/json":
                raise Refused(415, "the body must be JSON (Content-Type: application/json)")
        except Refused as r:
            self._refuse(r)

    def data_received(self, chunk: bytes) -> None:
        # a body over the limit is read and dropped (never kept), then refused in post()
        self._size += len(chunk)
        if self._size <= BODY_LIMIT:
            self._chunks.append(chunk)
        else:
            self._chunks = []

    def get(self, call: str) -> None:  # pragma: no cover - prepare() already refused it
        self._refuse(Refused(405, "use POST"))

    async def post(self, call: str) -> None:
        if self._finished:
            return
        studio: Studio = self.settings["studio"]
        try:
            if self._size > BODY_LIMIT:
                raise Refused(
                    413, f"the request is too large ({self._size:,} bytes; at most {BODY_LIMIT:,})"
                )
            try:
                body = json.loads(b"".join(self._chunks).decode("utf-8") or "null")
            except (UnicodeDecodeError, json.JSONDecodeError) as exc:
                raise Refused(400, f"the request body is not valid JSON: {exc}") from None
            if not isinstance(body, dict):
                raise Refused(400, "the request body must be a JSON object")
            fn, slow = studio.calls.get(call, (None, False))
            if fn is None:
                raise Refused(404, f"no such call: {call!r}")
            pool = studio.slow_pool if slow else studio.fast_pool
            loop = asyncio.get_running_loop()
            started = time.perf_counter()
            answer, cpu = await loop.run_in_executor(pool, _timed, fn, body)
            wall = 1000 * (time.perf_counter() - started)
            self.set_header("Server-Timing", f"app;dur={wall:.1f}, cpu;dur={1000 * cpu:.1f}")
        except Refused as r:
            return self._refuse(r)
        except MachdynError as exc:
            self.set_status(422)
            return self._json({"error": str(exc), "kind": type(exc).__name__, **_key_of(exc)})
        except RecursionError:
            self.set_status(400)
            return self._json({"error": "the document is nested too deeply to be read"})
        except Exception as exc:
            log.error("studio: %s failed:\n%s", call, traceback.format_exc())
            self.set_status(500)
            return self._json(
                {"error": f"internal error in {call}: {type(exc).__name__}: {exc}", "kind": "bug"}
            )
        from .exports import FileAnswer

        if isinstance(answer, FileAnswer):
            self.set_header("Content-Type", answer.mime)
            self.set_header("Content-Disposition", f'attachment; filename="{answer.filename}"')
            return self.finish(answer.data)
        self._json(answer)

    def _json(self, data: Any) -> None:
        self.set_header("Content-Type", "application/json; charset=utf-8")
        self.finish(json.dumps(data, allow_nan=False, separators=(",", ":")))


def _timed(fn: Callable[[dict], Any], body: dict) -> tuple[Any, float]:
    """``fn(body)`` and the CPU seconds its worker thread spent on it (for Server-Timing)."""
    t0 = time.thread_time()
    return fn(body), time.thread_time() - t0


def _key_of(exc: Exception) -> dict[str, Any]:
    path = getattr(exc, "path", None)
    out: dict[str, Any] = {}
    if path:
        out["key"] = ".".join(str(p) for p in path)
    field = getattr(exc, "field", None)
    if field and "key" not in out:
        out["key"] = str(field)
    return out


class Studio:
    """A studio server on 127.0.0.1 (``port=0``: any free port).

    ``file`` is the machine file the page opens and *Save* writes; nothing
    else on the disk is read or written.

    Examples
    --------
    >>> s = Studio(port=0)
    >>> url = s.start()
    >>> url.startswith("http://127.0.0.1:")
    True
    >>> s.stop()
    """

    def __init__(self, file: str | Path | None = None, *, port: int = 0) -> None:
        from .._validate import count
        from ..errors import InputError

        port = count("port", port, minimum=0)
        if port > 65535:
            raise InputError("port", f"must be at most 65535, got {port}")
        self.file = None if file is None else Path(file).resolve()
        self.port = port
        self.fast_pool = ThreadPoolExecutor(1, thread_name_prefix="studio-fast")
        self.slow_pool = ThreadPoolExecutor(1, thread_name_prefix="studio-slow")
        from .calls import calls

        self.calls: dict[str, tuple[Callable[[dict], Any], bool]] = calls(self)
        self._thread: threading.Thread | None = None
        self._loop: tornado.ioloop.IOLoop | None = None
        self._server: tornado.httpserver.HTTPServer | None = None
        #: Called (in the server's thread) once it listens: ``serve_forever`` only.
        self.on_ready: Callable[[], None] | None = None

    @property
    def url(self) -> str:
        """The page's address."""
        return f"http://127.0.0.1:{self.port}/"

    def _app(self) -> tornado.web.Application:
        return tornado.web.Application(
            [
                (r"/", PageHandler),
                (r"/static/(.*)", StaticHandler, {"path": str(STATIC)}),
                (r"/api/([a-z_]+)", ApiHandler),
            ],
            studio=self,
            compress_response=False,  # loopback: compressing costs more than it saves
        )

    def _listen(self) -> None:
        import socket

        sockets = tornado.netutil.bind_sockets(self.port, "127.0.0.1", family=socket.AF_INET)
        self.port = sockets[0].getsockname()[1]
        self._server = tornado.httpserver.HTTPServer(
            self._app(), max_body_size=16 * BODY_LIMIT, xheaders=False
        )
        self._server.add_sockets(sockets)

    def start(self) -> str:
        """Serve in a background thread; returns the page's address."""
        import tornado.netutil

        ready = threading.Event()
        errors: list[BaseException] = []

        def run() -> None:
            asyncio.set_event_loop(asyncio.new_event_loop())
            try:
                self._loop = tornado.ioloop.IOLoop.current()
                self._listen()
            except BaseException as exc:
                errors.append(exc)
                ready.set()
                return
            ready.set()
            self._loop.start()

        self._thread = threading.Thread(target=run, name="machdyn-studio", daemon=True)
        self._thread.start()
        ready.wait()
        if errors:
            raise errors[0]
        return self.url

    def serve_forever(self) -> None:
        """Serve in this thread until interrupted (Ctrl-C)."""
        import tornado.netutil

        asyncio.set_event_loop(asyncio.new_event_loop())
        self._loop = tornado.ioloop.IOLoop.current()
        self._listen()
        if self.on_ready is not None:
            self._loop.add_callback(self.on_ready)
        self.fast_pool.submit(self._warm_up)
        try:
            self._loop.start()
        finally:
            self._close()

    def _warm_up(self) -> None:
        """Analyse a template once, so the first real answer does not pay the imports."""
        try:
            from .analysis import analyse
            from .templates import template

            analyse(template("four-bar"), samples=36, quantities=[])
        except Exception:  # never worth a failed start
            log.debug("studio: warm-up failed", exc_info=True)

    def _close(self) -> None:
        if self._server is not None:
            self._server.stop()
        self.fast_pool.shutdown(wait=False, cancel_futures=True)
        self.slow_pool.shutdown(wait=False, cancel_futures=True)

    def stop(self) -> None:
        """Stop a server started with :meth:`start`."""
        loop = self._loop
        if loop is None:
            return
        done = threading.Event()

        def halt() -> None:
            self._close()
            loop.stop()
            done.set()

        loop.add_callback(halt)
        done.wait(5)
        if self._thread is not None:
            self._thread.join(5)
        self._loop = None
