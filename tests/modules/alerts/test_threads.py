"""Which event a notice is about (VOEvent 2.0 citations, GCN trigger ids within a stream) and the
note that keeps it in the task archive (pure)."""

from __future__ import annotations

import pytest

from nightcrew.modules.alerts import NoticeError, parse_notice
from nightcrew.modules.alerts._threads import EventRequest, Threads, read_note, request_note

from .voevents import STREAM, notice


def test_a_citation_puts_a_notice_in_the_thread_of_the_notice_it_cites() -> None:
    threads = Threads(10)
    first = parse_notice(notice("pos1", trigger=""))
    key = threads.key(first)
    assert key == f"{STREAM}#pos1"
    threads.remember(first.ivorn, key)
    followup = parse_notice(notice("xrt", trigger="", cites=(("followup", first.ivorn),)))
    threads.remember(followup.ivorn, threads.key(followup))
    # Citing the follow-up reaches the thread's first notice: the graph is followed, not one step.
    later = parse_notice(notice("uvot", trigger="", cites=(("supersedes", followup.ivorn),)))
    assert threads.key(later) == key and threads.cited_keys(later, "supersedes") == [key]


def test_a_trigger_id_is_the_same_event_only_within_its_stream() -> None:
    threads = Threads(10)
    swift = parse_notice(notice("pos1", trigger="1001"))
    fermi = parse_notice(
        notice("pos1", trigger="1001").replace(STREAM.encode(), b"ivo://nightcrew.test/FERMI")
    )
    assert threads.key(swift) == f"{STREAM}#trigger 1001"
    assert threads.key(fermi) == "ivo://nightcrew.test/FERMI#trigger 1001"


def test_a_gcn_retraction_without_citations_withdraws_its_trigger() -> None:
    threads = Threads(10)
    withdrawn = parse_notice(notice("retr", ra=None, retraction=True))
    assert withdrawn.retraction and threads.cited_keys(withdrawn, "retraction") == [f"{STREAM}#trigger 1001"]


@pytest.mark.parametrize("cite", ["", "refers"])
def test_a_citation_must_say_how_it_cites(cite: str) -> None:
    payload = notice("pos2", cites=((cite, f"{STREAM}#pos1"),))
    expected = f"the citation of {STREAM}#pos1 has cite='{cite}'; expected followup"
    with pytest.raises(NoticeError, match=expected):
        parse_notice(payload)


def test_the_archive_note_keeps_notice_event_and_error_and_restores_the_threads() -> None:
    read = parse_notice(notice("pos1", error=0.05))
    note = request_note(read, f"{STREAM}#trigger 1001")
    assert read_note(note) == (read.ivorn, f"{STREAM}#trigger 1001", 0.05)
    assert read_note("taken by hand") is None
    threads = Threads(10)
    assert threads.restore([("7", note), ("8", "a person's note")]) == 1
    assert threads.seen(read.ivorn) and threads.request(f"{STREAM}#trigger 1001") == EventRequest("7", 0.05)


def test_the_memory_is_bounded() -> None:
    threads = Threads(2)
    for name in ("a", "b", "c"):
        threads.remember(name, name)
    assert not threads.seen("a") and threads.seen("b") and threads.seen("c")
