"""The daemon's statement watchdog: a statement running past the store's time limit is stopped,
whatever it computes inside one row.

ArcadeDB checks its limit (`arcadedb.command.timeout`) and a terminated query only between rows:
an expression evaluated inside one row (a `reduce` over a range, nested list comprehensions) never
looks, and keeps a core and gigabytes of heap for minutes. The watchdog asks the store to terminate
a query past the limit (`RunningQuery.terminate`: enough for one that is between rows); a query
still running `GRACE_S` later has an exception thrown into its thread through JVMTI `StopThread`
(the debugger interface: `Thread.stop` does nothing from Java 20 on), never while the thread is
committing; a full GC then gives the heap it took back to the system.
"""
from __future__ import annotations

import ctypes
import threading
import time
from typing import Any, Callable, Optional

GRACE_S = 0.5          # past the limit, before a query that ignored its termination is stopped
LOOK_S = 0.25          # how often the watchdog looks at the running queries
VP = ctypes.c_void_p
JNI_VERSION = 0x00150000     # JNI_VERSION_21
JVMTI_VERSION = 0x30010200   # JVMTI_VERSION_1_2
CAN_SIGNAL_THREAD = 1 << 10  # jvmtiCapabilities.can_signal_thread


class _ThreadInfo(ctypes.Structure):
    _fields_ = [("name", VP), ("priority", ctypes.c_int), ("is_daemon", ctypes.c_ubyte),
                ("thread_group", VP), ("context_class_loader", VP)]


def _function(owner: VP, index: int, restype: Any, *argtypes: Any) -> Any:
    """Entry `index` of the JNI/JVMTI function table `owner` points to."""
    table = ctypes.cast(owner, ctypes.POINTER(ctypes.POINTER(VP)))[0]
    return ctypes.CFUNCTYPE(restype, *argtypes)(table[index])


def _libjvm() -> ctypes.CDLL:
    with open("/proc/self/maps") as maps:
        for line in maps:
            if line.rstrip().endswith("/libjvm.so"):
                return ctypes.CDLL(line.split()[-1])
    raise OSError("no libjvm.so in this process")


class Jvmti:
    """JVMTI's StopThread for the calling (JVM-attached) thread: the tables' entries used, by
    their index in jni.h / jvmti.h."""

    def __init__(self) -> None:
        lib = _libjvm()
        vm, n = VP(), ctypes.c_int()
        lib.JNI_GetCreatedJavaVMs.argtypes = [ctypes.POINTER(VP), ctypes.c_int, ctypes.POINTER(ctypes.c_int)]
        if lib.JNI_GetCreatedJavaVMs(ctypes.byref(vm), 1, ctypes.byref(n)) != 0 or n.value != 1:
            raise OSError("no Java VM in this process")
        get_env = _function(vm, 6, ctypes.c_int, VP, ctypes.POINTER(VP), ctypes.c_int)
        self.env, self.jvmti = VP(), VP()
        if get_env(vm, ctypes.byref(self.env), JNI_VERSION) or get_env(vm, ctypes.byref(self.jvmti), JVMTI_VERSION):
            raise OSError("this thread has no JNI or JVMTI environment")
        caps = (ctypes.c_uint32 * 4)(CAN_SIGNAL_THREAD)
        if _function(self.jvmti, 141, ctypes.c_int, VP, VP)(self.jvmti, ctypes.cast(caps, VP)):
            raise OSError("the Java VM refuses the can_signal_thread capability")
        j, e = self.jvmti, self.env
        self._all_threads = _function(j, 3, ctypes.c_int, VP, ctypes.POINTER(ctypes.c_int), ctypes.POINTER(ctypes.POINTER(VP)))
        self._stop = _function(j, 6, ctypes.c_int, VP, VP, VP)
        self._thread_info = _function(j, 8, ctypes.c_int, VP, VP, ctypes.POINTER(_ThreadInfo))
        self._deallocate = _function(j, 46, ctypes.c_int, VP, VP)
        self._find_class = _function(e, 6, VP, VP, ctypes.c_char_p)
        self._push_frame = _function(e, 19, ctypes.c_int, VP, ctypes.c_int)
        self._pop_frame = _function(e, 20, VP, VP, VP)
        self._method = _function(e, 33, VP, VP, VP, ctypes.c_char_p, ctypes.c_char_p)
        self._new_object = _function(e, 30, VP, VP, VP, VP, ctypes.POINTER(VP))
        self._new_string = _function(e, 167, VP, VP, ctypes.c_char_p)

    def stop_thread(self, name: str, message: str) -> bool:
        """Throw a RuntimeException(`message`) into the Java thread named `name` (unique); whether
        one was found and signalled."""
        if self._push_frame(self.env, 64):
            return False
        try:
            count, threads = ctypes.c_int(), ctypes.POINTER(VP)()
            if self._all_threads(self.jvmti, ctypes.byref(count), ctypes.byref(threads)):
                return False
            target = None
            for i in range(count.value):
                info = _ThreadInfo()
                if self._thread_info(self.jvmti, threads[i], ctypes.byref(info)) == 0:
                    if info.name and ctypes.string_at(info.name) == name.encode():
                        target = threads[i]
                    self._deallocate(self.jvmti, info.name)
            self._deallocate(self.jvmti, ctypes.cast(threads, VP))
            if target is None:
                return False
            cls = self._find_class(self.env, b"java/lang/RuntimeException")
            init = self._method(self.env, cls, b"<init>", b"(Ljava/lang/String;)V")
            args = (VP * 1)(self._new_string(self.env, message.encode()))
            return self._stop(self.jvmti, target, self._new_object(self.env, cls, init, args)) == 0
        finally:
            self._pop_frame(self.env, None)


def _committing(thread: Any) -> bool:
    """Whether `thread` is inside a commit (never stopped there: the store's files would be half written)."""
    return any("commit" in str(f.getMethodName()).lower() for f in thread.getStackTrace())


class Watchdog(threading.Thread):
    """Stops, in the daemon, every Bolt statement running longer than `limit_s` (see the module;
    statements through the store's HTTP API, sg3d's own `db check`, keep the store's own limit)."""

    def __init__(self, java_server: Any, limit_s: float, log: Callable[[str], None] = print) -> None:
        super().__init__(name="sg3d-statement-watchdog", daemon=True)
        self.server, self.limit_s, self.log = java_server, limit_s, log
        self.stopped_queries: list = []     # stopped, waiting to end: then a GC gives their heap back

    def run(self) -> None:
        import jpype

        jpype.JClass("java.lang.Thread").currentThread()   # attaches this thread to the JVM
        try:
            jvmti: Optional[Jvmti] = Jvmti()
        except OSError as exc:
            self.log(f"statement watchdog: only between rows ({exc})")
            jvmti = None
        while True:
            time.sleep(LOOK_S)
            try:
                self.look(jvmti)
            except Exception as exc:  # noqa: BLE001 - the watchdog must outlive any one look
                self.log(f"statement watchdog: {exc}")

    def look(self, jvmti: Optional[Jvmti]) -> None:
        if self.stopped_queries and all(q.isEnded() for q in self.stopped_queries):
            self.stopped_queries.clear()
            import jpype

            jpype.JClass("java.lang.System").gc()    # a full GC uncommits the heap the statement took
        for query in list(self.server.getRunningQueries().getRunning()):
            elapsed = query.getElapsedMillis() / 1000.0
            # Bolt only: what sg3d and its users send; the HTTP API carries sg3d's own checks
            if query.isEnded() or elapsed < self.limit_s or str(query.getProtocol()) != "bolt":
                continue
            why = f"the statement ran past the store's {self.limit_s:g} s limit and was stopped"
            if not query.isTerminated():
                query.terminate(why)
            elif elapsed >= self.limit_s + GRACE_S and jvmti is not None:
                self._stop(query, jvmti, why)

    def _stop(self, query: Any, jvmti: Jvmti, why: str) -> None:
        thread = self._thread_of(query)
        if thread is None or _committing(thread):
            return
        name = str(thread.getName())
        tag = f"sg3d-stopping-{id(query)}-{time.monotonic_ns()}"
        thread.setName(tag)
        try:
            if jvmti.stop_thread(tag, why) and query not in self.stopped_queries:
                self.stopped_queries.append(query)
                self.log(f"statement watchdog: stopped {str(query.getText())[:120]!r} after "
                         f"{query.getElapsedMillis() / 1000:.1f} s")
        finally:
            thread.setName(name)

    @staticmethod
    def _thread_of(query: Any) -> Any:
        """The Bolt connection thread running `query` (the query names its connection)."""
        import jpype

        executor = jpype.JClass("com.arcadedb.bolt.BoltNetworkExecutor")
        field = executor.class_.getDeclaredField("connectionId")
        field.setAccessible(True)
        connection = str(query.getConnectionId())
        for thread in jpype.JClass("java.lang.Thread").getAllStackTraces().keySet():
            if isinstance(thread, executor) and str(field.get(thread)) == connection:
                return thread
        return None
