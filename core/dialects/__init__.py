"""What each dialect means: a code table each (G/M codes, modal groups, addresses, help texts)."""
