"""catwalk.garment"""
