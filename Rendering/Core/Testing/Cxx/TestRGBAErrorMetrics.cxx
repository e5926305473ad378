int TestRGBAErrorMetrics(int, char*[])
{
  return 1;
}
