"""One run of a program: the Simulation on virtual time and its RunResult (run.py), what is
written of a run (output.py: the JSON document and the summary; vcd.py: the trace and its
GTKWave save file) and W608, the program's writes of specials the simulator does not model
(unmodelled.py).

Belongs here: what `mlc sim PROGRAM --stimulus FILE`, the debugger, `mlc run` and the ladder
reports run and show; it imports the machine, engines/, hardware/ and stimulus/.
Does not belong here: many runs (campaign/), the stepping of a debugging session
(mlctool/debug/).
"""
