"""The interpreter: Program → Toolpath.

One run loop for every dialect (loop.py) runs the blocks in order, follows calls, repeated sections and
jumps (run.py) and keeps checkpoints for the next run of the same document (checkpoints.py); what a block
means is the dialect's machine: milling (mill_machine.py over the block executor pal_mill.py) and TRAUB
turning (traub_turn.py, its cycles in traub_cycles.py).
"""
