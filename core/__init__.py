"""PAL Trainer core: the pure pipeline parse → interpret → simulate → grade, and the CLI."""
