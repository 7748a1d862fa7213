"""The browser studio (viser): mode palette, live sketch, optimization and playback for one shared
sketch."""
