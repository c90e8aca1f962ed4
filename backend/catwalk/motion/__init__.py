"""catwalk.motion"""
