#!/usr/bin/env python3
"""`penalty view` against hostile folders and hostile clients (docs/viewer.md, "The server"; the
rows of docs/reliability.md, "The viewer and its server").

Usage: view_server_safety.py PENALTY_EXECUTABLE WORK_DIR

Symbolic links: a link in the viewer folder to a file outside it (or inside it) is never served,
and the writer (`penalty view DIR --no-serve`, `penalty run --view DIR`) replaces links in DIR by
its own files instead of writing through them. Slow clients, over real sockets: 32 and 300
half-sent requests do not keep a new client from its 200; a client trickling a byte a second is
cut at the request deadline with 408; a request head over 16 KiB is 431, one of exactly 16 KiB
is served. Deadlines below only decide whether a behaviour happened (generous bounds, never a
speed measurement). Prints one line per check; exits 1 at the first failure.
"""
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import time

penalty, work = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)


def check(condition, what):
    if not condition:
        print(f"FAIL: {what}")
        sys.exit(1)
    print(f"ok: {what}")


def run(*args, expect=0):
    p = subprocess.run([penalty, *args], capture_output=True, text=True, timeout=300)
    check(p.returncode == expect, f"penalty {' '.join(args)} -> exit {p.returncode} (expected {expect})\n{p.stdout}{p.stderr}")
    return p


view = os.path.join(work, "view")
run("run", "--steps", "5", "--quiet", "--view", view, "--no-serve")

# ---- 1. the writer never writes through a link
victims = {}
def link_to_victim(name):
    victim = os.path.join(work, f"victim-{name}.txt")
    with open(victim, "w") as f:
        f.write(f"precious {name}\n")
    victims[name] = victim
    path = os.path.join(view, name)
    if os.path.lexists(path):
        os.remove(path)
    os.symlink(os.path.relpath(victim, view), path)


# a run.json that is a link is refused by `penalty view` (the server would refuse to serve it)
link_to_victim("run.json")
p = run("view", view, "--no-serve", expect=1)
check("run.json' is a symbolic link" in p.stderr, "penalty view names a run.json that is a link")
check(open(victims["run.json"]).read() == "precious run.json\n", "penalty view left run.json's target untouched")
os.remove(os.path.join(view, "run.json"))
run("run", "--steps", "5", "--quiet", "--view", view, "--no-serve")
for name in ("index.html", "viewer.js", "topology.u32", "positions.f32", "contacts.f32", "run.json.tmp"):
    link_to_victim(name)
run("view", view, "--no-serve")  # rewrites the page files
link_to_victim("run.json")
for name in ("index.html", "viewer.js"):
    path = os.path.join(view, name)
    check(not os.path.islink(path) and os.path.isfile(path) and os.path.getsize(path) > 1000,
          f"penalty view --no-serve replaced the link {name} by the page file")
check(open(victims["index.html"]).read() == "precious index.html\n",
      "penalty view --no-serve left the file a link DIR/index.html -> ../victim pointed at untouched")
run("run", "--steps", "5", "--quiet", "--view", view, "--no-serve")  # every data file, and run.json via run.json.tmp
for name, victim in victims.items():
    check(open(victim).read() == f"precious {name}\n", f"penalty run --view: the target of the link DIR/{name} is untouched")
for name in ("topology.u32", "positions.f32", "contacts.f32", "run.json"):
    path = os.path.join(view, name)
    check(not os.path.islink(path) and os.path.isfile(path), f"penalty run --view wrote DIR/{name} as a regular file")
check(not any(n.startswith(".") for n in os.listdir(view)), "no temporary file is left in DIR")

# links the server must not follow: out of DIR, inside DIR, a FIFO, a sub-directory
secret = os.path.join(work, "secret.txt")
with open(secret, "w") as f:
    f.write("secret outside the viewer folder\n")
os.symlink(secret, os.path.join(view, "secret.txt"))
if os.path.exists("/etc/passwd"):
    os.symlink("/etc/passwd", os.path.join(view, "passwd"))
os.symlink("run.json", os.path.join(view, "alias.json"))
os.mkfifo(os.path.join(view, "fifo.json"))
os.mkdir(os.path.join(view, "sub"))

# ---- 2. the server
server = subprocess.Popen([penalty, "view", view, "--port", "0"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
try:
    match = re.search(r"http://127\.0\.0\.1:(\d+)/", server.stdout.readline())
    check(match is not None, "penalty view prints the address it serves")
    port = int(match.group(1))

    def request(raw, timeout=10):
        """Sends `raw` whole, half-closes, returns (status line, whole answer) or ('error ...', b'')."""
        try:
            with socket.create_connection(("127.0.0.1", port), timeout=timeout) as s:
                s.sendall(raw)
                s.shutdown(socket.SHUT_WR)
                answer = b""
                while chunk := s.recv(65536):
                    answer += chunk
        except OSError as e:
            return f"error {e!r}", b""
        return answer.split(b"\r\n")[0].decode(errors="replace"), answer

    def get(target, headers=b""):
        return request(b"GET " + target.encode() + b" HTTP/1.1\r\nHost: 127.0.0.1\r\n" + headers + b"\r\n")

    status, body = get("/run.json")
    check(" 200 " in status and body.endswith(open(os.path.join(view, "run.json"), "rb").read()), "run.json is served whole")
    for name in ("secret.txt", "passwd", "alias.json", "fifo.json", "sub"):
        if name == "passwd" and not os.path.lexists(os.path.join(view, name)):
            continue
        status, body = get("/" + name)
        check((" 404 " in status or " 403 " in status) and b"secret" not in body and b"root:" not in body,
              f"a {'FIFO' if name == 'fifo.json' else 'sub-directory' if name == 'sub' else 'symbolic link'} "
              f"DIR/{name} is not served: {status}")

    # request heads: 16 KiB counted exactly
    line = b"GET /run.json HTTP/1.1\r\nHost: 127.0.0.1\r\n"
    def head_of(size):
        filler = size - len(line) - len(b"X: \r\n\r\n")
        return line + b"X: " + b"a" * filler + b"\r\n\r\n"
    check(len(head_of(16384)) == 16384, "the test's head has 16384 bytes")
    check(" 200 " in request(head_of(16384))[0], "a request head of exactly 16 KiB (16384 bytes) is served")
    check(" 431 " in request(head_of(16385))[0], "a request head of 16385 bytes is 431")
    status, _ = request(b"GET / HTTP/1.1\r\nX: " + b"a" * 20000 + b"\r\n\r\n")
    check(" 431 " in status, f"a 20 000-byte header line is 431: {status}")
    status, _ = request(line + (b"X-Many: " + b"b" * 6000 + b"\r\n") * 3 + b"\r\n")
    check(" 431 " in status, f"three 6 000-byte header lines (18 KiB in all) are 431: {status}")
    status, _ = request(b"POST / HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Length: 200000\r\n\r\n" + b"z" * 200000)
    check(" 405 " in status, f"a POST with a 200 kB body gets its 405 whole (drained, not reset): {status}")
    status, _ = request(b"GET / HTTP/1.1\r\nHost: attacker.example\r\n\r\n")
    check(" 421 " in status, f"a foreign Host (DNS rebinding) is 421: {status}")
    status, _ = request(b"GET / HTTP/1.1\r\nHost: localhost:8123\r\n\r\n")
    check(" 200 " in status, f"Host localhost:8123 (a forwarded port) is served: {status}")

    # slowloris: half-sent requests held open, then a new client
    for count in (32, 300):
        held = []
        for _ in range(count):
            s = socket.create_connection(("127.0.0.1", port), timeout=10)
            s.sendall(b"GET /run.json HTTP/1.1\r\nHost: 127.0.0.1\r\n")  # no empty line: the head never ends
            held.append(s)
        time.sleep(0.5)  # let the server accept them all before the new client comes
        status, _ = get("/run.json")
        check(" 200 " in status, f"a new client gets 200 while {count} half-sent requests are open: {status}")
        for s in held:
            s.close()

    # a trickler: one byte a second keeps every single read short, never the whole request
    with socket.create_connection(("127.0.0.1", port), timeout=5) as s:
        s.sendall(b"GET /run.json HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: ")
        started, answer, cut = time.monotonic(), b"", False
        while time.monotonic() - started < 40 and not cut:
            try:
                s.sendall(b"a")
            except OSError:
                cut = True
                break
            s.settimeout(1.0)
            try:
                chunk = s.recv(4096)
                answer += chunk
                cut = chunk == b"" or b"\r\n\r\n" in answer
            except socket.timeout:
                pass
            except OSError:
                cut = True
        elapsed = time.monotonic() - started
    check(cut and elapsed < 40, f"a client trickling a byte a second is cut at the request deadline (after {elapsed:.0f} s)")
    check(answer.startswith(b"HTTP/1.1 408 "), f"... with 408 Request Timeout: {answer[:40]!r}")

    check(" 200 " in get("/")[0], "the server still serves after all of the above")
finally:
    server.send_signal(signal.SIGTERM)
    try:
        code = server.wait(timeout=30)
    except subprocess.TimeoutExpired:
        server.kill()
        code = None
check(code == 0, f"penalty view stops on SIGTERM with exit code 0 (got {code})")
print("all view server checks passed")
