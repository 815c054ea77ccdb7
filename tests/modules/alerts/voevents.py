"""Sample VOEvent 2.0 notices written by the tests (valid against the schema comet checks)."""

from __future__ import annotations

from datetime import datetime

STREAM = "ivo://nightcrew.test/GRB"


def notice(
    name: str,
    *,
    ra: float | None = 56.75,
    dec: float | None = 24.12,
    error: float = 0.1,
    role: str = "observation",
    packet_type: int = 61,
    trigger: str = "1001",
    at: datetime | None = None,
    cites: tuple[tuple[str, str], ...] = (),
    retraction: bool = False,
) -> bytes:
    """A GRB position notice ``STREAM#name`` (no WhereWhen when ``ra`` is None)."""
    when = (
        f"<ISOTime>{at:%Y-%m-%dT%H:%M:%S}</ISOTime>"
        if at is not None
        else "<ISOTime>2024-01-15T20:00:00</ISOTime>"
    )
    where = (
        ""
        if ra is None
        else f"""
  <WhereWhen>
    <ObsDataLocation>
      <ObservatoryLocation id="GEOLUN"/>
      <ObservationLocation>
        <AstroCoordSystem id="UTC-FK5-GEO"/>
        <AstroCoords coord_system_id="UTC-FK5-GEO">
          <Time unit="s"><TimeInstant>{when}</TimeInstant></Time>
          <Position2D unit="deg">
            <Name1>RA</Name1><Name2>Dec</Name2>
            <Value2><C1>{ra}</C1><C2>{dec}</C2></Value2>
            <Error2Radius>{error}</Error2Radius>
          </Position2D>
        </AstroCoords>
      </ObservationLocation>
    </ObsDataLocation>
  </WhereWhen>"""
    )
    citations = "".join(f'<EventIVORN cite="{cite}">{ivorn}</EventIVORN>' for cite, ivorn in cites)
    return f"""<?xml version="1.0" encoding="UTF-8"?>
<voe:VOEvent xmlns:voe="http://www.ivoa.net/xml/VOEvent/v2.0"
  ivorn="{STREAM}#{name}" role="{role}" version="2.0">
  <Who><AuthorIVORN>ivo://nightcrew.test/author</AuthorIVORN><Date>2024-01-15T20:00:00</Date></Who>
  <What>
    <Param name="Packet_Type" value="{packet_type}"/>
    <Param name="TrigID" value="{trigger}"/>
    <Param name="Retraction" value="{str(retraction).lower()}"/>
  </What>{where}
  {f"<Citations>{citations}</Citations>" if citations else ""}
</voe:VOEvent>
""".encode()
