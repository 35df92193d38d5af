"""`mlc mcp` (mlctool/agents/): the MCP SDK's own client starts the server over stdio, lists
the tools and calls every one; check and sim give structured results (issue 32)."""

from __future__ import annotations

import asyncio
import sys

from mcp import Client
from mcp.client.stdio import StdioServerParameters

from tests.conftest import ROOT, SAMPLES

CONVEYOR = str(SAMPLES / "nc5" / "conveyor.il")
STIM = str(SAMPLES / "nc5" / "conveyor.stim")
TOOLS = {"check", "explain", "build", "sim", "ladder", "debug_start", "debug_step", "debug_read",
         "debug_force", "debug_back", "debug_stop"}


async def _session() -> dict:
    params = StdioServerParameters(command=sys.executable, args=["-m", "mlctool", "mcp"],
                                   env={"PYTHONPATH": str(ROOT)}, cwd=str(ROOT))
    out = {}
    async with Client(params) as client:
        out["tools"] = {t.name: t for t in (await client.list_tools()).tools}

        async def call(name, **args):
            r = await client.call_tool(name, args)
            return r.is_error, r.structured_content, r.content

        out["check_bad"] = await call("check", source="LD X0\nOUT Q9\nEND\n")
        out["check_ok"] = await call("check", files=[CONVEYOR])
        out["explain"] = await call("explain", code="E603")
        out["explain_bad"] = await call("explain", code="Z999")
        out["build"] = await call("build", files=[CONVEYOR])
        out["sim"] = await call("sim", files=[CONVEYOR], stimulus=STIM, watch=["Y0", "D0"],
                                trace_from_ms=0, trace_to_ms=2000)
        out["sim_fail"] = await call("sim", source="LD X0\nOUT Y0\nEND\n",
                                     stimulus_text="0ms X0=1\n10ms expect Y0=0\nrun 20ms\n")
        out["ladder"] = await call("ladder", files=[CONVEYOR])
        _, started, _ = await call("debug_start", files=[CONVEYOR], stimulus=STIM)
        out["debug_start"] = started
        sid = started["session"]
        out["debug_force"] = await call("debug_force", session=sid, device="M0", value="1")
        out["debug_step"] = await call("debug_step", session=sid, scans=True, count=3)
        out["debug_read"] = await call("debug_read", session=sid, devices=["Y0", "M0", "D0"])
        out["debug_back"] = await call("debug_back", session=sid, scans=True)
        out["debug_stop"] = await call("debug_stop", session=sid)
        out["debug_gone"] = await call("debug_read", session=sid, devices=["Y0"])
    return out


def test_an_mcp_client_lists_and_calls_every_tool():
    r = asyncio.run(asyncio.wait_for(_session(), 60))
    assert set(r["tools"]) == TOOLS
    assert all(t.description and t.input_schema["type"] == "object" for t in r["tools"].values())
    err, bad, _ = r["check_bad"]
    assert not err and bad["errors"] >= 1
    first = bad["diagnostics"][0]
    assert first["line"] == 2 and first["code"].startswith("E") and "Q9" in first["message"]
    err, ok, _ = r["check_ok"]
    assert not err and ok["errors"] == 0 and ok["target"] == "nc5"
    assert r["explain"][1]["code"] == "E603" and "expect" in r["explain"][1]["doc"]
    assert r["explain_bad"][0] is True  # a tool error, with its message
    assert r["build"][1]["ok"] and r["build"][1]["steps"] > 10
    err, run, _ = r["sim"]
    assert not err and run["ok"] and run["expectations"]["failed"] == 0 and run["expectations"]["passed"] > 0
    assert set(run["devices"]) == {"Y0", "D0"} and run["trace"]["changes"]
    assert all(0 <= c["time_ms"] <= 2000 for c in run["trace"]["changes"])
    err, failed, _ = r["sim_fail"]
    assert not failed["ok"] and failed["expectations"]["failures"][0]["device"] == "Y0"
    assert r["ladder"][1]["svg"].startswith("<svg")
    assert r["debug_start"]["ok"] and r["debug_start"]["scan"] == 0
    assert r["debug_force"][1]["forced"] is True
    assert r["debug_step"][1]["scan"] == 3
    assert r["debug_read"][1]["values"]["M0"] == 1
    assert r["debug_back"][1]["scan"] == 2
    assert r["debug_stop"][1] == {"closed": r["debug_start"]["session"]}
    assert r["debug_gone"][0] is True
